#!/usr/bin/env python3
"""The live preview in a real headless Chromium, driven over the DevTools protocol (a pipe, no
extra packages): the page converges past a few spp, a drag orbits the camera (the image changes
and the accumulation starts over), a click selects the tall box and a drag moves it, its material
is edited through the page's form, and the compaction flag is switched off. Then (issue 33): a
second page stays in step with the first (camera and flags; D on the first turns the server's
denoise on, the second's box follows and the first's frames are denoised), the target spp lowered below the
current count ends the render there and says so, a rejected max depth goes back to the value in
force with its message next to the field, frames arrive during a 30 Hz drag (a bare relative
path served from its folder, at a size whose samples are slow enough for coarse frames), a .glb
opened directly shows its camera, and Ctrl-C writes -o and says so, or says nothing is written.
Screenshots of each step go to --out.

Exit 0 passed, 1 failed, 77 skipped (no chromium, or a pathtracer built without the server).
usage: serve_browser_test.py --pathtracer BIN --scene SCENE.json --out DIR
"""
import argparse
import base64
import json
import math
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

SKIP = 77


class DevTools:
    """Chromium's --remote-debugging-pipe: JSON messages ended by NUL on fds 3 (in) and 4 (out)."""

    def __init__(self, chromium, profile):
        to_chrome_r, self.to_chrome = os.pipe()
        self.from_chrome, from_chrome_w = os.pipe()
        # The browser reads fd 3 and writes fd 4: a shell puts our pipe ends there.
        command = [chromium, "--headless=new", "--remote-debugging-pipe", "--no-sandbox",
                   "--disable-gpu", "--no-first-run", "--no-default-browser-check",
                   "--user-data-dir=" + profile, "--window-size=1280,900", "about:blank"]
        self.proc = subprocess.Popen(
            ["bash", "-c", f'exec "$@" 3<&{to_chrome_r} 4>&{from_chrome_w}', "bash"] + command,
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(to_chrome_r, from_chrome_w))
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self.buffer = b""
        self.next_id = 0
        self.session = None

    def call(self, method, params=None, session=True, timeout=30):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        os.write(self.to_chrome, json.dumps(message).encode() + b"\0")
        deadline = time.time() + timeout
        while time.time() < deadline:
            while b"\0" not in self.buffer:
                chunk = os.read(self.from_chrome, 1 << 20)
                if not chunk:
                    raise RuntimeError("chromium closed the DevTools pipe")
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
        raise RuntimeError(f"{method}: no answer in {timeout} s")

    def open(self, url):
        """A new page (tab) at url; later calls go to it. Returns its session (see use)."""
        target = self.call("Target.createTarget", {"url": "about:blank"}, session=False)
        attached = self.call("Target.attachToTarget",
                             {"targetId": target["targetId"], "flatten": True}, session=False)
        self.session = attached["sessionId"]
        self.call("Page.enable")
        self.call("Page.navigate", {"url": url})
        return self.session

    def use(self, session):
        self.session = session

    def eval(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                "returnByValue": True})
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def mouse(self, kind, x, y, buttons=0):
        self.call("Input.dispatchMouseEvent",
                  {"type": kind, "x": x, "y": y, "button": "left" if kind != "mouseMoved" or buttons
                   else "none", "buttons": buttons, "clickCount": 1 if kind != "mouseMoved" else 0})

    def key(self, key, code):
        for kind in ("keyDown", "keyUp"):
            self.call("Input.dispatchKeyEvent", {"type": kind, "key": key, "code": code,
                                                 "windowsVirtualKeyCode": ord(key.upper())})

    def drag(self, x0, y0, dx, dy, steps=8):
        self.mouse("mousePressed", x0, y0, 1)
        time.sleep(0.2)  # the page picks on press; moves before the answer are queued anyway
        for i in range(1, steps + 1):
            self.mouse("mouseMoved", x0 + dx * i / steps, y0 + dy * i / steps, 1)
            time.sleep(0.03)
        self.mouse("mouseReleased", x0 + dx, y0 + dy, 0)

    def screenshot(self, path):
        data = self.call("Page.captureScreenshot", {"format": "png"})["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def close(self):
        try:
            self.call("Browser.close", session=False, timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


def wait_for(check, what, timeout=60):
    deadline = time.time() + timeout
    error = None
    while time.time() < deadline:
        try:
            value = check()
            if value:
                return value
        except RuntimeError as e:  # the page is still loading
            error = e
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}" + (f" (last error: {error})" if error else ""))


# A checksum of the image the page shows, drawn into a canvas.
IMAGE_SUM = """(async () => { const img = document.getElementById('view');
  await img.decode().catch(() => {}); if (!img.naturalWidth) return null;
  const c = document.createElement('canvas'); c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data; let s = 0;
  for (let i = 0; i < d.length; i += 4) s += d[i] + 3 * d[i + 1] + 7 * d[i + 2];
  return s; })()"""

FETCH_JSON = "fetch('{}', {{cache: 'no-store'}}).then(r => r.json())"


def set_value(dt, element, value, event="change"):
    """A control set as a user sets it: its value, then the event the page listens to."""
    dt.eval(f"(() => {{ const e = document.getElementById('{element}'); e.value = {json.dumps(value)};"
            f" e.dispatchEvent(new Event('{event}')); }})()")


def text_of(dt, element):
    return dt.eval(f"document.getElementById('{element}').textContent")


def start_server(pathtracer, scene, cwd, extra):
    """pathtracer SCENE --serve 0 EXTRA in cwd: (process, port), or (process, None) with the
    message when it did not start."""
    server = subprocess.Popen([pathtracer, scene, "--serve", "0"] + extra, cwd=cwd,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    said = ""
    for _ in range(50):  # a model file's summary line may come first
        line = server.stderr.readline()
        said += line
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
        if match:
            return server, int(match.group(1))
        if not line:
            break
    server.kill()
    server.wait()
    return server, said


def interrupt(server):
    """Ctrl-C: the exit status and what the server said after its first line."""
    server.send_signal(signal.SIGINT)
    rest = server.stderr.read()
    return server.wait(timeout=30), rest


def write_glb(path):
    """A floor quad and a perspective camera "overview" at (0, 1, 3), as one .glb."""
    positions = struct.pack("<12f", -1, 0, -1, -1, 0, 1, 1, 0, 1, 1, 0, -1)
    indices = struct.pack("<6I", 0, 1, 2, 0, 2, 3)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
           "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 1, 3], "name": "eye"}],
           "cameras": [{"type": "perspective", "name": "overview",
                        "perspective": {"yfov": 0.8, "znear": 0.01, "aspectRatio": 1.0}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                          "min": [-1, 0, -1], "max": [1, 0, 1]},
                         {"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                           {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
           "buffers": [{"byteLength": 72}]}
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary = positions + indices
    total = 12 + 8 + len(text) + 8 + len(binary)
    with open(path, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total))
        f.write(struct.pack("<I4s", len(text), b"JSON") + text)
        f.write(struct.pack("<I4s", len(binary), b"BIN\0") + binary)


def run(args, dt, port, out):
    dt.open(f"http://127.0.0.1:{port}/")
    state = lambda: dt.eval("({spp: preview.spp, generation: preview.generation})")
    first = wait_for(lambda: (s := state()) and s["spp"] >= args.converge and s, "convergence")
    print(f"converged past {args.converge} spp: {first['spp']} spp")
    dt.screenshot(os.path.join(out, "1_converged.png"))
    rect = dt.eval("(() => { const r = document.getElementById('view').getBoundingClientRect();"
                   " return [r.left, r.top, r.width, r.height]; })()")
    left, top, width, height = rect
    before_sum = wait_for(lambda: dt.eval(IMAGE_SUM), "the image's pixels")

    # Orbit: a drag that starts on the room (nothing selected yet).
    before = state()
    dt.drag(left + width * 0.5, top + height * 0.15, width * 0.2, 0)
    orbited = wait_for(lambda: (s := state()) and s["generation"] > before["generation"] and s,
                       "the orbit's frame")
    assert orbited["spp"] < before["spp"], f"accumulation not restarted: {before} -> {orbited}"
    after_sum = wait_for(lambda: (v := dt.eval(IMAGE_SUM)) and v != before_sum and v, "a changed image")
    print(f"orbit: generation {orbited['generation']}, spp {before['spp']} -> {orbited['spp']}, "
          f"image sum {before_sum} -> {after_sum}")
    dt.screenshot(os.path.join(out, "2_orbited.png"))

    # Back to the file's camera, then select the tall box by a click and drag it right.
    dt.eval("document.getElementById('c-reset').click()")
    # Reset once the server's camera (the one picks use) sees the tall box (object 6) there.
    pick = ("fetch('/api/pick', {method: 'POST', headers: {'Content-Type': 'application/json'},"
            " body: JSON.stringify({x: 18.5, y: 30.5})}).then(r => r.json())")
    wait_for(lambda: dt.eval(pick)["object"] == 6, "the camera reset")
    bx, by = left + width * 18.5 / 48, top + height * 30.5 / 48
    dt.mouse("mousePressed", bx, by, 1)
    dt.mouse("mouseReleased", bx, by, 0)
    selection = wait_for(lambda: (t := dt.eval("document.getElementById('selection').textContent"))
                         and t.startswith("object ") and t, "a selection")
    assert selection.startswith("object 6 "), selection
    x_before = dt.eval(FETCH_JSON.format("/api/scene.json"))["objects"][6]["transform"]["translate"][0]
    dt.drag(bx, by, width * 0.15, 0)
    moved = wait_for(lambda: (d := dt.eval(FETCH_JSON.format("/api/scene.json")))
                     ["objects"][6]["transform"]["translate"][0] > x_before + 0.1 and d, "the move")
    print(f"selected \"{selection}\"; moved x {x_before:.3f} -> "
          f"{moved['objects'][6]['transform']['translate'][0]:.3f}")
    wait_for(lambda: state()["spp"] >= 2, "the moved box's frame")
    dt.screenshot(os.path.join(out, "3_moved.png"))

    # The selected box's material (white, index 0) made blue through the page's form.
    dt.eval("(() => { const f = document.getElementById('material');"
            " [0.1, 0.2, 0.9].forEach((v, i) => { const e = f.elements['albedo.' + i]; e.value = v;"
            " e.dispatchEvent(new Event('change')); }); })()")
    albedo = lambda: dt.eval(FETCH_JSON.format("/api/scene.json"))["materials"]["white"]["albedo"]
    wait_for(lambda: albedo() == [0.1, 0.2, 0.9], "the material edit")
    print(f"material edited through the form: white albedo {albedo()}")

    # Compaction off, as a user picks it in the Flags section.
    dt.eval("(() => { const s = document.getElementById('f-compact'); s.value = 'off';"
            " s.dispatchEvent(new Event('change')); })()")
    stats = wait_for(lambda: (s := dt.eval(FETCH_JSON.format("/api/stats")))
                     and s.get("compact_used") is False and s["spp"] >= 1 and s, "compaction off")
    print(f"compaction off: compact_used {stats['compact_used']} at {stats['spp']} spp")
    dt.screenshot(os.path.join(out, "4_compaction_off.png"))
    return rect


def two_pages(dt, port, out, page_a, rect):
    """A second page follows the first's camera, flags and display, also after a reload."""
    left, top, width, height = rect
    page_b = dt.open(f"http://127.0.0.1:{port}/")
    wait_for(lambda: dt.eval("preview.state !== null && preview.frames > 0"), "the second page")
    dt.use(page_a)
    dt.drag(left + width * 0.5, top + height * 0.15, -width * 0.15, height * 0.05)
    set_value(dt, "f-sort", "material")
    set_value(dt, "d-exposure", 2, "input")
    wait_for(lambda: dt.eval("preview.state.options.sort === 'material' && interacting === 0 && "
                             "preview.state.display.exposure === 2"), "page A's edits")
    time.sleep(0.3)  # the last camera edit's state event
    camera_a = dt.eval("preview.state.camera")
    dt.use(page_b)
    seen = lambda: dt.eval("({camera: preview.state.camera, sort: document.getElementById('f-sort').value,"
                           " exposure: document.getElementById('d-exposure').value})")
    b = wait_for(lambda: (v := seen()) and v["camera"] == camera_a and v["sort"] == "material"
                 and v["exposure"] == "2" and v, "page B in step")
    dt.call("Page.reload")
    time.sleep(0.3)
    wait_for(lambda: (v := seen()) and v["camera"] == camera_a and v["exposure"] == "2", "page B reloaded")
    dt.screenshot(os.path.join(out, "5_second_page.png"))
    print(f"second page in step: camera {b['camera']['position']}, sort {b['sort']}, exposure "
          f"{b['exposure']} (also after a reload)")
    # D on page A: the server's denoise option, shown on page B; page A's frames denoised.
    dt.use(page_a)
    assert dt.eval("!document.getElementById('f-denoise-row').hidden"), "no denoise toggle shown"
    dt.key("d", "KeyD")
    denoise_ms = wait_for(lambda: dt.eval("preview.stats && preview.stats.denoise_ms"),
                          "a denoised frame")
    dt.use(page_b)
    wait_for(lambda: dt.eval("document.getElementById('f-denoise').checked"), "page B's denoise box")
    dt.use(page_a)
    print(f"D pressed on page A: page B shows denoise on; frames denoised in {denoise_ms:.1f} ms")
    dt.key("d", "KeyD")
    wait_for(lambda: dt.eval("preview.state.options.denoise === false"), "denoise off again")


def lowered_spp_and_rejected_value(dt, out):
    """Target spp below the current count ends the render there and says so; a refused max depth
    goes back to the value in force with its message next to the field."""
    wait_for(lambda: dt.eval("preview.spp") >= 4, "a few spp")
    set_value(dt, "f-spp", 2)
    message = wait_for(lambda: (t := text_of(dt, "s-state")) and "ends at" in t and t, "the stop message")
    # The message comes with the state; the frame at that count may still be on its way (a slow
    # encode under the sanitizers): wait for it, then no frame may change the count.
    ended = int(re.search(r"ends at (\d+) spp", message).group(1))
    wait_for(lambda: dt.eval("preview.spp") == ended, "the frame at the count the message names")
    time.sleep(1.0)
    assert dt.eval("preview.spp") == ended, "frames went on after the target was lowered"
    assert "(stopped)" in text_of(dt, "status"), text_of(dt, "status")
    dt.screenshot(os.path.join(out, "6_spp_lowered.png"))
    print(f"target lowered to 2 at {ended} spp: \"{message}\"")
    set_value(dt, "f-spp", 100000)
    wait_for(lambda: dt.eval("preview.state.options.spp") == 100000, "the target raised again")
    depth = dt.eval("preview.state.options.max_depth")
    set_value(dt, "f-max-depth", -1)
    note = wait_for(lambda: dt.eval("(() => { const n = document.querySelector('.field-error');"
                                    " return n && n.previousElementSibling.contains("
                                    "document.getElementById('f-max-depth')) && n.textContent; })()"),
                    "the message next to max depth")
    value = dt.eval("document.getElementById('f-max-depth').value")
    assert value == str(depth), f"max depth shows {value}, the render uses {depth}"
    dt.screenshot(os.path.join(out, "7_rejected_value.png"))
    print(f"max depth -1 refused: the field shows {value} again, next to it: \"{note}\"")


def drag_frames(args, dt, out, pathtracer):
    """A bare relative path served from its folder; a 3 s drag at 30 Hz shows frames throughout."""
    folder, name = os.path.split(os.path.abspath(args.scene))
    server, port = start_server(pathtracer, name, folder, ["--width", "160", "--height", "160",
                                                           "--spp", "100000", "--threads", "1"])
    assert isinstance(port, int), f"{name} from its folder did not start: {port}"
    try:
        dt.open(f"http://127.0.0.1:{port}/")
        wait_for(lambda: dt.eval("preview.spp") >= 2, "the bare path's frames")
        left, top, width, height = dt.eval(
            "(() => { const r = document.getElementById('view').getBoundingClientRect();"
            " return [r.left, r.top, r.width, r.height]; })()")
        before = dt.eval("({frames: preview.frames, ...preview.framesByKind})")
        x, y = left + width * 0.5, top + height * 0.2
        dt.mouse("mousePressed", x, y, 1)
        time.sleep(0.1)
        start = time.time()
        i = 0
        while time.time() - start < 3.0:
            i += 1
            dt.mouse("mouseMoved", x + 40 * math.sin(i / 15), y, 1)
            time.sleep(max(0.0, start + i / 30 - time.time()))
        during = dt.eval("({frames: preview.frames, ...preview.framesByKind})")
        dt.mouse("mouseReleased", x, y, 0)
        frames = during["frames"] - before["frames"]
        coarse = during["coarse"] - before["coarse"]
        dt.screenshot(os.path.join(out, "8_drag.png"))
        print(f"30 Hz drag for 3 s ({i} moves) at 160x160 on 1 thread: {frames} frames shown "
              f"({coarse} coarse)")
        assert frames >= 6, f"only {frames} frames during the drag"
        status, said = interrupt(server)
        assert status == 0 and "nothing is written" in said, f"Ctrl-C without -o: {status} {said}"
        print(f"Ctrl-C without -o: {said.strip().splitlines()[-1]}")
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()


def model_file(dt, out, pathtracer, folder):
    """A .glb opened directly, its camera in force and offered; Ctrl-C writes -o."""
    write_glb(os.path.join(folder, "floor.glb"))
    server, port = start_server(pathtracer, "floor.glb", folder,
                                ["--width", "64", "--height", "64", "--spp", "100000",
                                 "--threads", "1", "-o", "saved.png"])
    assert isinstance(port, int), f"floor.glb did not start: {port}"
    try:
        dt.open(f"http://127.0.0.1:{port}/")
        wait_for(lambda: dt.eval("preview.spp") >= 2, "the model's frames")
        cameras = dt.eval("[...document.getElementById('c-choice').options].map(o => o.textContent)")
        assert any("overview" in c for c in cameras), cameras
        position = dt.eval("preview.state.camera.position")
        assert [round(v, 4) for v in position] == [0, 1, 3], position
        dt.screenshot(os.path.join(out, "9_glb.png"))
        print(f"floor.glb served: camera at {position}, cameras offered {cameras}")
        status, said = interrupt(server)
        saved = os.path.join(folder, "saved.png")
        assert status == 0 and "wrote saved.png" in said and os.path.getsize(saved) > 0, \
            f"Ctrl-C with -o: {status} {said}"
        print(f"Ctrl-C with -o: {said.strip().splitlines()[-1]}")
    finally:
        if server.poll() is None:
            server.kill()
            server.wait()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--pathtracer", required=True)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--converge", type=int, default=8)
    args = parser.parse_args()
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if not chromium:
        print("skipped: no chromium")
        return SKIP
    os.makedirs(args.out, exist_ok=True)
    server = subprocess.Popen(
        [args.pathtracer, args.scene, "--serve", "0", "--width", "48", "--height", "48",
         "--spp", "100000", "--threads", "1"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    line = server.stderr.readline()
    match = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    if not match:
        server.wait()
        rest = server.stderr.read()
        if "no preview server" in line + rest:
            print("skipped: pathtracer was built without the preview server")
            return SKIP
        print(f"the server did not start: {line}{rest}")
        return 1
    profile = tempfile.mkdtemp(prefix="pt-chromium-")
    dt = DevTools(chromium, profile)
    try:
        port = int(match.group(1))
        rect = run(args, dt, port, args.out)
        page_a = dt.session
        two_pages(dt, port, args.out, page_a, rect)
        lowered_spp_and_rejected_value(dt, args.out)
        pathtracer = os.path.abspath(args.pathtracer)
        drag_frames(args, dt, args.out, pathtracer)
        models = tempfile.mkdtemp(prefix="pt-serve-model-")
        try:
            model_file(dt, args.out, pathtracer, models)
        finally:
            shutil.rmtree(models, ignore_errors=True)
        print(f"passed; screenshots in {args.out}")
        return 0
    except (AssertionError, RuntimeError) as e:
        print(f"FAILED: {e}")
        return 1
    finally:
        dt.close()
        shutil.rmtree(profile, ignore_errors=True)
        server.terminate()
        server.wait()


if __name__ == "__main__":
    sys.exit(main())
