#!/usr/bin/env python3
"""Latency and frame rate of the live preview (pathtracer --serve), measured as a page sees it.

Starts `pathtracer SCENE --serve 0` with the given size and backend, waits for the first frame,
then sends N camera edits (a small orbit each), one at a time: for each, the time from sending
the POST to receiving the first frame of its generation (the long poll /api/frame), and the
server's own edit_to_frame_ms. Then it lets the render run for --seconds and counts frames and
samples per second. Prints one summary line per quantity (median, p90) and, with --json, writes
them. With --move-object N the edits move object N instead (by +-0.05 in x): an instance takes
the top-level path, any other object a scene rebuild; the server's rebuild time is reported.
With --orbit-seconds S it first orbits continuously for S seconds, a camera edit every 1/30 s
(as a mouse drag sends them), while another connection long-polls frames as the page does: the
frames shown per second during the orbit (by kind: coarse frames at reduced resolution, full
frames) are the issue-33 target (>= 4 on 2 CPU cores, >= 20 on an H100, Cornell box at 512^2).
With --denoise the server starts with the page's denoise toggle on (frames shown denoised; the
last frame's denoise time is reported). Standard library only.

  python3 benchmarks/serve_latency.py --pathtracer build/pathtracer --scene scenes/cornell_box.json \
      --width 512 --height 512 --backend cpu
  # GPU, 1080p (the lead's run): --backend cuda --width 1920 --height 1080
  # Instance moves in the 10^4-bunny field (benchmarks/scenes/make_bunny_field.py):
  #   --scene benchmarks/scenes/bunny_field_10k.json --move-object 500 (a quad: --move-object 0)
"""
import argparse
import http.client
import json
import math
import re
import statistics
import subprocess
import sys
import threading
import time


class Client:
    def __init__(self, port):
        self.port = port

    def request(self, method, path, body=None):
        c = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        headers = {"Content-Type": "application/json"} if body is not None else {}
        c.request(method, path, body=json.dumps(body) if body is not None else None, headers=headers)
        r = c.getresponse()
        data = r.read()
        c.close()
        return r.status, dict(r.getheaders()), data

    def frame(self, after):
        status, headers, _ = self.request("GET", f"/api/frame?after={after}")
        if status != 200:
            return None
        return {k: int(headers[h]) for k, h in
                (("id", "X-Frame-Id"), ("generation", "X-Generation"), ("spp", "X-Spp"))}


def orbit_camera(camera, angle):
    """The camera's eye turned by `angle` radians about the vertical through its look-at point."""
    p, t = camera["position"], camera["look_at"]
    dx, dz = p[0] - t[0], p[2] - t[2]
    c, s = math.cos(angle), math.sin(angle)
    return [t[0] + c * dx + s * dz, p[1], t[2] - s * dx + c * dz]


def continuous_orbit(client, camera, seconds, rate=30.0):
    """Camera edits at `rate` Hz for `seconds` while frames are long-polled: frames shown/s."""
    moving = threading.Event()
    moving.set()
    posts = []

    def drag():
        start = time.perf_counter()
        i = 0
        while time.perf_counter() - start < seconds:
            position = orbit_camera(camera, 0.01 * i)
            sent = time.perf_counter()
            status, _, _ = client.request("POST", "/api/camera", {"position": position})
            posts.append((time.perf_counter() - sent) * 1e3)
            if status != 200:
                break
            i += 1
            time.sleep(max(0.0, start + i / rate - time.perf_counter()))
        moving.clear()

    first = client.frame(0)
    while first is None:
        first = client.frame(0)
    last_id = first["id"]
    thread = threading.Thread(target=drag)
    start = time.perf_counter()
    thread.start()
    kinds, widths = {}, []
    while moving.is_set():
        status, headers, _ = client.request("GET", f"/api/frame?after={last_id}")
        if status != 200 or not moving.is_set():
            continue
        last_id = int(headers["X-Frame-Id"])
        kind = headers.get("X-Frame-Kind", "render")
        kinds[kind] = kinds.get(kind, 0) + 1
        widths.append(int(headers.get("X-Width", 0)))
    elapsed = time.perf_counter() - start
    thread.join()
    shown = sum(kinds.values())
    return {"orbit_seconds": elapsed, "orbit_edits": len(posts),
            "orbit_edits_per_s": len(posts) / elapsed,
            "orbit_post_ms_median": statistics.median(posts) if posts else None,
            "orbit_frames_per_s": shown / elapsed, "orbit_frames_by_kind": kinds,
            "orbit_frame_width_median": statistics.median(widths) if widths else None}


def percentile(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(math.ceil(p / 100 * len(s))) - 1)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pathtracer", default="build/pathtracer")
    ap.add_argument("--scene", default="scenes/cornell_box.json")
    ap.add_argument("--width", type=int, default=512)
    ap.add_argument("--height", type=int, default=512)
    ap.add_argument("--backend", default="auto")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--edits", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--move-object", type=int, help="edits move this object, not the camera")
    ap.add_argument("--orbit-seconds", type=float, default=0.0,
                    help="first orbit at 30 Hz this long and count the frames shown")
    ap.add_argument("--denoise", action="store_true",
                    help="start with the page's denoise on (full frames shown denoised)")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()

    command = [args.pathtracer, args.scene, "--serve", "0", "--width", str(args.width),
               "--height", str(args.height), "--spp", "1000000", "--backend", args.backend,
               "--quiet"]
    if args.threads:
        command += ["--threads", str(args.threads)]
    if args.denoise:
        command += ["--denoise"]
    server = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    line = server.stderr.readline()
    match = re.search(r"http://[^:]+:(\d+)/", line)
    if not match:
        print("the server did not start:", line + server.stderr.read(), file=sys.stderr)
        return 1
    client = Client(int(match.group(1)))
    try:
        _, _, scene = client.request("GET", "/api/scene")
        camera = json.loads(scene)["camera"]
        orbit = {}
        if args.orbit_seconds > 0:
            orbit = continuous_orbit(client, dict(camera), args.orbit_seconds)
            time.sleep(0.5)
        last = client.frame(0)
        while last is None:  # the long poll ends after 2 s; a first denoised frame may take longer
            last = client.frame(0)
        latencies, server_ms, first_spp, rebuild_ms = [], [], [], []
        for i in range(args.edits):
            sign = 1 if i % 2 == 0 else -1
            if args.move_object is not None:
                path = f"/api/objects/{args.move_object}/move"
                edit = {"translate": [0.05 * sign, 0, 0]}
            else:
                # A small orbit: the eye moves sideways around the look-at point.
                camera["position"] = orbit_camera(camera, 0.02 * sign)
                path, edit = "/api/camera", {"position": camera["position"]}
            sent = time.perf_counter()
            status, _, body = client.request("POST", path, edit)
            if status != 200:
                print(f"POST {path}: {status} {body.decode()}", file=sys.stderr)
                return 1
            generation = json.loads(body)["generation"]
            while True:
                f = client.frame(last["id"])
                if f is None:
                    continue
                last = f
                if f["generation"] >= generation:
                    break
            latencies.append((time.perf_counter() - sent) * 1e3)
            first_spp.append(f["spp"])
            _, _, stats = client.request("GET", "/api/stats")
            stats = json.loads(stats)
            if "edit_to_frame_ms" in stats and stats["generation"] == generation:
                server_ms.append(stats["edit_to_frame_ms"])
            if args.move_object is not None and "rebuilds" in stats:
                rebuild_ms.append(stats["rebuilds"]["last_ms"])
        # Steady state: frames and samples per second with no edits.
        start = time.perf_counter()
        first = last
        frames = 0
        while time.perf_counter() - start < args.seconds:
            f = client.frame(last["id"])
            if f:
                last = f
                frames += 1
        elapsed = time.perf_counter() - start
        _, _, stats = client.request("GET", "/api/stats")
        stats = json.loads(stats)
        result = {
            "scene": args.scene, "width": args.width, "height": args.height,
            "backend": stats.get("backend"), "device": stats.get("device"),
            "edits": args.edits, "edit": "camera" if args.move_object is None
            else f"move object {args.move_object}",
            "edit_to_frame_ms_median": statistics.median(latencies),
            "edit_to_frame_ms_p90": percentile(latencies, 90),
            "server_edit_to_frame_ms_median": statistics.median(server_ms) if server_ms else None,
            "first_frame_spp_median": statistics.median(first_spp),
            "frames_per_s": frames / elapsed,
            "spp_per_s": (last["spp"] - first["spp"]) / elapsed,
            "samples_per_s": stats.get("samples_per_s"),
            "rays_per_s": stats.get("rays_per_s"),
            "rebuilds": stats.get("rebuilds"),
            "rebuild_ms_median": statistics.median(rebuild_ms) if rebuild_ms else None,
            "denoise": args.denoise, "denoise_ms": stats.get("denoise_ms"),
        }
        result.update(orbit)
        print(f"{args.scene} {args.width}x{args.height} on {result['backend']} ({result['device']})")
        if orbit:
            print(f"  30 Hz orbit for {orbit['orbit_seconds']:.1f} s ({orbit['orbit_edits_per_s']:.1f} "
                  f"edits/s sent): {orbit['orbit_frames_per_s']:.1f} frames/s shown "
                  f"{orbit['orbit_frames_by_kind']}, median width {orbit['orbit_frame_width_median']}")
        print(f"  edit -> first frame (client): median {result['edit_to_frame_ms_median']:.1f} ms, "
              f"p90 {result['edit_to_frame_ms_p90']:.1f} ms over {args.edits} edits "
              f"({result['edit']}) "
              f"(first frame at {result['first_frame_spp_median']:.0f} spp)")
        if server_ms:
            print(f"  edit -> frame encoded (server): median {result['server_edit_to_frame_ms_median']:.1f} ms")
        if rebuild_ms:
            r = result["rebuilds"]
            print(f"  rebuild per move: median {result['rebuild_ms_median']:.1f} ms "
                  f"({r['scene']} scene rebuilds, {r['top_level']} top-level rebuilds)")
        print(f"  steady: {result['frames_per_s']:.1f} frames/s, {result['spp_per_s']:.1f} spp/s, "
              f"{result['samples_per_s'] / 1e6:.2f} M samples/s, {result['rays_per_s'] / 1e6:.2f} M rays/s")
        if args.denoise:
            print(f"  denoised frames: the last took {result['denoise_ms'] or 0:.1f} ms to denoise")
        if args.json:
            with open(args.json, "w") as f:
                json.dump(result, f, indent=2)
        return 0
    finally:
        server.terminate()
        server.wait()


if __name__ == "__main__":
    sys.exit(main())
