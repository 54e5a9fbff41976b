"""Shared pieces of the accuracy study (benchmarks/accuracy.py): settings, image I/O,
error measures, scene scaling, the run log and runner, the cost model and plan."""
import argparse
import csv
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REL_EPS = 1e-2  # the relMSE denominator's constant (cli.md)

# ----------------------------------------------------------------------------------------
# Configurations of part 2. The baseline passes every studied flag explicitly, so rows such
# as "rr 3" or "compact on" are the baseline's runs, not re-runs (listed as aliases).
BASE = {"integrator": "mis", "adaptive": "off", "rr": "3", "depth": 8, "compact": "on",
        "sort": "off", "film": "float", "lp": "all", "denoise": "off"}
# name, study group, tier (1: changes the estimator; 2: should change only time), overrides,
# render-cost multiplier for the planner.
CONFIGS = [
    ("mis", "integrator", 1, {}, 1.0),
    ("nee", "integrator", 1, {"integrator": "nee"}, 1.0),
    ("bsdf", "integrator", 1, {"integrator": "bsdf"}, 0.9),
    ("adaptive on", "adaptive", 1, {"adaptive": "on"}, 1.0),
    ("rr 1", "russian roulette", 1, {"rr": "1"}, 0.8),
    ("rr 8", "russian roulette", 1, {"rr": "8"}, 1.3),
    ("rr off", "russian roulette", 1, {"rr": "off"}, 1.3),
    ("depth 2", "max depth", 1, {"depth": 2}, 0.5),
    ("depth 4", "max depth", 1, {"depth": 4}, 0.8),
    ("direct only", "light paths", 1, {"lp": "direct"}, 1.0),
    ("indirect only", "light paths", 1, {"lp": "indirect"}, 1.0),
    ("compact off", "compaction", 2, {"compact": "off"}, 1.3),
    ("sort material", "sorting", 2, {"sort": "material"}, 1.7),
    ("film double", "film", 2, {"film": "double"}, 1.05),
    # --denoise: relMSE of the denoised image against render + denoise time (docs/denoise.md)
    ("denoise on", "denoising", 1, {"denoise": "on"}, 1.1),
]
ALIASES = {"adaptive": "adaptive off", "russian roulette": "rr 3", "max depth": "depth 8",
           "light paths": "all light", "compaction": "compact on", "sorting": "sort off",
           "film": "film float", "denoising": "denoise off"}
GROUP_ORDER = ["integrator", "adaptive", "russian roulette", "max depth", "light paths",
               "compaction", "sorting", "film", "denoising"]
REF_SEEDS = (1000001, 1000002)

DEFAULT_SCENES = ["scenes/cornell_glass_mirror.json:128x128",
                  "benchmarks/scenes/bunny_cornell.json:192x108",
                  "scenes/glossy_spheres.json:128x96"]
GLOSSY_FALLBACK = "scenes/mesh_scene.json"
QUICK_SIZE = {128: 16, 192: 24, 108: 14, 96: 12}


def settings(cfg_over):
    s = dict(BASE)
    s.update(cfg_over)
    return s


FLAG_NAMES = {"integrator": "--integrator", "adaptive": "--adaptive", "rr": "--rr-depth",
              "depth": "--max-depth", "compact": "--compact", "sort": "--sort", "film": "--film",
              "lp": "--light-paths"}


def flags_of(s):
    out = []
    for k, flag in FLAG_NAMES.items():
        out += [flag, str(s[k])]
    if s.get("denoise") == "on":  # a flag without a value
        out.append("--denoise")
    return out


def ref_key(s):
    return (int(s["depth"]), s["lp"])


def ref_name(key):
    return "depth%d_%s" % key


# ----------------------------------------------------------------------------------------
# Images and metrics.
def read_pfm(path):
    """A PFM as float64 (height, width, 3), rows top to bottom."""
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    while len(tokens) < 4:  # "PF", width, height, scale: whitespace separated
        while data[pos:pos + 1].isspace():
            pos += 1
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        tokens.append(data[pos:end].decode())
        pos = end
    pos += 1  # the single whitespace after the scale
    if tokens[0] != "PF":
        raise ValueError("%s: only 3-channel PFM (PF) is read" % path)
    w, h, scale = int(tokens[1]), int(tokens[2]), float(tokens[3])
    img = np.frombuffer(data, "<f4" if scale < 0 else ">f4", w * h * 3, pos)
    return img.reshape(h, w, 3)[::-1].astype(np.float64)


def write_pfm(path, img):
    img = np.ascontiguousarray(np.asarray(img, np.float32)[::-1])
    with open(path, "wb") as f:
        f.write(b"PF\n%d %d\n-1\n" % (img.shape[1], img.shape[0]))
        f.write(img.astype("<f4").tobytes())


def read_exr(path):
    """Channels of a scanline EXR (NONE, ZIPS or ZIP compression, as our renderer writes),
    as {name: float64 (height, width)}, rows top to bottom."""
    with open(path, "rb") as f:
        b = f.read()
    if b[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("%s is not an EXR" % path)
    i, attrs = 8, {}
    while b[i] != 0:
        j = b.index(b"\0", i)
        name = b[i:j].decode()
        i = j + 1
        j = b.index(b"\0", i)
        typ = b[i:j].decode()
        i = j + 1
        size = struct.unpack_from("<i", b, i)[0]
        i += 4
        attrs[name] = (typ, b[i:i + size])
        i += size
    i += 1
    chans, raw, k = [], attrs["channels"][1], 0
    while raw[k] != 0:
        j = raw.index(b"\0", k)
        nm = raw[k:j].decode()
        k = j + 1
        chans.append((nm, struct.unpack_from("<i", raw, k)[0]))
        k += 16
    comp = attrs["compression"][1][0]
    if comp not in (0, 2, 3):
        raise ValueError("%s: EXR compression %d is not read here (NONE/ZIPS/ZIP only)"
                         % (path, comp))
    lines = 16 if comp == 3 else 1
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    nchunks = (h + lines - 1) // lines
    offsets = struct.unpack_from("<%dQ" % nchunks, b, i)
    dt = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}
    out = {nm: np.zeros((h, w), np.float64) for nm, _ in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", b, off)
        data = b[off + 8:off + 8 + size]
        n = min(lines, y1 + 1 - y)
        expect = n * w * sum(dt[p].itemsize for _, p in chans)
        if comp != 0 and size < expect:
            t = np.frombuffer(zlib.decompress(data), np.uint8).astype(np.int64)
            t[1:] -= 128
            t = (np.cumsum(t) & 0xFF).astype(np.uint8)
            half = (len(t) + 1) // 2
            r = np.empty_like(t)
            r[0::2] = t[:half]
            r[1::2] = t[half:]
            data = r.tobytes()
        pos = 0
        for row in range(n):
            for nm, p in chans:
                out[nm][y - y0 + row] = np.frombuffer(data, dt[p], w, pos)
                pos += w * dt[p].itemsize
    return out


def relmse(x, r):
    """cli.md: mean((x - r)^2 / (r^2 + 1e-2)) over pixels and channels."""
    return float(np.mean((x - r) ** 2 / (r * r + REL_EPS)))


def mae(x, r):
    return float(np.mean(np.abs(x - r)))


# ----------------------------------------------------------------------------------------
# Scene files: JSON with // and /* */ comments.
def strip_comments(text):
    out, i, n, in_str = [], 0, len(text), False
    while i < n:
        c = text[i]
        if in_str:
            out.append(c)
            if c == "\\":
                out.append(text[i + 1:i + 2])
                i += 1
            elif c == '"':
                in_str = False
        elif c == '"':
            in_str = True
            out.append(c)
        elif text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        elif text.startswith("/*", i):
            i = text.index("*/", i) + 2
            continue
        else:
            out.append(c)
        i += 1
    return "".join(out)


def load_scene(path):
    with open(path) as f:
        return json.loads(strip_comments(f.read()))


def scaled_scene(scene, s, src_dir):
    """The scene with geometry, camera and point lights scaled by s about the origin. With
    emissive lighting only, the image must not change (scene-format.md)."""
    d = json.loads(json.dumps(scene))
    cam = d["camera"]
    for k in ("position", "look_at"):
        cam[k] = [v * s for v in cam[k]]
    for k in ("aperture_radius", "focus_distance"):
        if k in cam:
            cam[k] = cam[k] * s
    for m in d.get("materials", {}).values():
        if "absorption" in m:
            m["absorption"] = [v / s for v in m["absorption"]]
    for light in d.get("lights", []):
        light["position"] = [v * s for v in light["position"]]
        light["intensity"] = [v * s * s for v in light["intensity"]]
    for o in d["objects"]:
        if "file" in o and not os.path.isabs(o["file"]):
            o["file"] = os.path.normpath(os.path.join(src_dir, o["file"]))
        t = o.get("transform")
        if t is None:
            o["transform"] = {"scale": s}
        elif "matrix" in t:
            m = list(t["matrix"])
            for i in range(12):
                m[i] *= s
            t["matrix"] = m
        else:
            sc = t.get("scale", 1.0)
            t["scale"] = [v * s for v in sc] if isinstance(sc, list) else sc * s
            if "translate" in t:
                t["translate"] = [v * s for v in t["translate"]]
    return d


# ----------------------------------------------------------------------------------------
class Log:
    def __init__(self, path):
        self.f = open(path, "w")

    def __call__(self, *args):
        line = " ".join(str(a) for a in args)
        print(line, flush=True)
        self.f.write(line + "\n")
        self.f.flush()


class Runner:
    """Runs the pathtracer; every run's numbers go to the CSV."""

    FIELDS = ["part", "scene", "config", "group", "spp", "seed", "width", "height",
              "render_s", "wall_s", "samples", "spp_mean", "nonfinite", "relmse", "mae", "ref",
              "status", "note"]

    def __init__(self, args, log, work, csv_path):
        self.binary, self.backend, self.threads = args.binary, args.backend, args.threads
        self.log, self.work = log, work
        self.csvf = open(csv_path, "w", newline="")
        self.csv = csv.DictWriter(self.csvf, fieldnames=self.FIELDS)
        self.csv.writeheader()
        self.device = None
        self.count = 0
        self.failures = 0

    def render(self, scene, w, h, spp, seed, flags, out=None, hdr=None, reference=None,
               timeout=600):
        """Returns (stats or None, image or None, wall seconds, error text)."""
        self.count += 1
        out = out or os.path.join(self.work, "run.pfm")
        stats_path = os.path.join(self.work, "run_stats.json")
        for p in (out, stats_path):
            if os.path.exists(p):
                os.remove(p)
        cmd = [self.binary, scene, "-o", out, "--stats-json", stats_path, "--quiet",
               "--backend", self.backend, "--width", str(w), "--height", str(h),
               "--spp", str(spp), "--seed", str(seed)] + list(flags)
        if self.backend == "cpu":
            cmd += ["--threads", str(self.threads)]
        if hdr:
            cmd += ["--hdr", hdr]
        if reference:
            cmd += ["--reference", reference]
        t0 = time.perf_counter()
        try:
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               timeout=timeout, text=True)
        except subprocess.TimeoutExpired:
            self.failures += 1
            return None, None, time.perf_counter() - t0, "timeout after %ds" % timeout
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            self.failures += 1
            err = "exit %d: %s" % (p.returncode, (p.stderr or "").strip()[-400:])
            self.log("  ! run failed:", " ".join(cmd[1:]), "->", err)
            return None, None, wall, err
        with open(stats_path) as f:
            stats = json.load(f)
        self.device = self.device or stats.get("device")
        img = read_pfm(out) if out.endswith(".pfm") else (read_pfm(hdr) if hdr and
                                                          hdr.endswith(".pfm") else None)
        return stats, img, wall, ""

    def row(self, **kw):
        r = {k: "" for k in self.FIELDS}
        r.update(kw)
        for k in ("render_s", "wall_s", "relmse", "mae"):
            if isinstance(r[k], float):
                r[k] = "%.6g" % r[k]
        self.csv.writerow(r)
        self.csvf.flush()


def stat_fields(stats, wall):
    # A denoised run's time is the render's plus the denoiser's.
    seconds = (stats["time_ms"]["render"] + stats["time_ms"].get("denoise", 0.0)) / 1000.0
    return dict(render_s=seconds, wall_s=wall,
                samples=stats.get("samples", ""), spp_mean=stats.get("spp_mean", ""),
                nonfinite=stats.get("nonfinite_samples", ""))


# ----------------------------------------------------------------------------------------
# The cost model used to plan within --budget-minutes.
class Costs:
    def __init__(self, backend):
        cuda = backend == "cuda"
        self.overhead = {}  # per scene: wall - render (process start, load, BVH, upload, write)
        self.thr = {}       # per scene: samples per render second at full load
        # Seen on an H100 (2026-11-21): 0.33 s per process on the Cornell scenes, 0.52 s on
        # the bunny (glb load + BVH build); 550 M samples/s at 128x128; ~4.5 ms per render.
        self.default_overhead = 0.40 if cuda else 0.10
        self.default_thr = 4.5e8 if cuda else 2.5e5
        self.r0 = 0.005 if cuda else 0.0  # fixed per-render cost (launches, waves)

    def run(self, scene, px, spp, mult=1.0):
        oh = self.overhead.get(scene, self.default_overhead)
        thr = self.thr.get(scene, self.default_thr)
        return oh + self.r0 + mult * px * spp / thr

    def calibrate(self, scene, records):
        """records: (wall, render_s, samples) of that scene's reference runs."""
        if not records:
            return
        oh = sorted(max(0.0, w - r) for w, r, _ in records)
        thr = sorted(s / r for _, r, s in records if r > 0)
        self.overhead[scene] = oh[len(oh) // 2]
        if thr:
            self.thr[scene] = thr[len(thr) // 2]


class Plan:
    """Part 2's budgets and seeds, trimmed step by step until the estimate fits."""

    LEVELS = [
        ("full: 6 budgets x 4 seeds", [1, 4, 16, 64, 256, 1024], 4, 4),
        ("tier-2 configs 2 seeds", [1, 4, 16, 64, 256, 1024], 4, 2),
        ("budgets from 4 spp", [4, 16, 64, 256, 1024], 4, 2),
        ("tier-1 configs 3 seeds", [4, 16, 64, 256, 1024], 3, 2),
        ("tier-1 configs 2 seeds", [4, 16, 64, 256, 1024], 2, 2),
        ("budgets 4..256 spp (2 decades)", [4, 16, 64, 256], 2, 2),
    ]

    def __init__(self, budgets, seeds1, seeds2, label):
        self.budgets, self.seeds1, self.seeds2, self.label = budgets, seeds1, seeds2, label

    def seeds(self, tier):
        return self.seeds1 if tier == 1 else self.seeds2

    def runs(self, scenes):
        out = []
        for si in range(max(self.seeds1, self.seeds2)):
            for spp in self.budgets:
                for sc in scenes:
                    for cfg in CONFIGS:
                        if si < self.seeds(cfg[2]):
                            out.append((sc, cfg, spp, si + 1))
        return out

    def cost(self, scenes, costs):
        return sum(costs.run(sc["path"], sc["px"], spp, cfg[4])
                   for sc, cfg, spp, _ in self.runs(scenes))


def choose_plan(args, scenes, costs, allowed):
    if args.quick:
        return Plan([4, 16], 2, 2, "quick: 2 budgets x 2 seeds")
    if args.budgets:
        b = [int(x) for x in args.budgets.split(",")]
        return Plan(b, args.seeds, min(args.seeds, args.seeds), "as given by --budgets/--seeds")
    for label, b, s1, s2 in Plan.LEVELS:
        p = Plan(b, min(s1, args.seeds), min(s2, args.seeds), label)
        if p.cost(scenes, costs) <= allowed:
            return p
    return p  # the smallest plan; the deadline guard skips what does not fit


# ----------------------------------------------------------------------------------------
def time_to(pts, level):
    """Render time at which the mean relMSE reaches `level`, interpolated log-log between
    budgets: (seconds, kind) with kind 'interp', 'below' (already at the first budget) or
    'extrap' (not reached; relMSE ~ 1/time from the last point)."""
    pts = [p for p in pts if p["relmse"] > 0 and p["time"] > 0 and math.isfinite(p["relmse"])]
    if not pts:
        return None
    if pts[0]["relmse"] <= level:
        return (pts[0]["time"], "below")
    for a, b in zip(pts, pts[1:]):
        if b["relmse"] <= level < a["relmse"]:
            la, lb = math.log(a["relmse"]), math.log(b["relmse"])
            f = (math.log(level) - la) / (lb - la)
            return (math.exp(math.log(a["time"]) + f * (math.log(b["time"]) -
                                                         math.log(a["time"]))), "interp")
    last = pts[-1]
    return (last["time"] * last["relmse"] / level, "extrap")


def fmt_t(t):
    if t is None:
        return "n/a"
    v, kind = t
    if kind == "below":
        return "< %.3g s" % v
    if kind == "extrap":
        return "not reached (~%.3g s)" % v
    return "%.3g s" % v
