"""GPU check of the Python module (run by benchmarks/python_check.sh on the GPU machine).

1. Identity: on the CUDA backend the module's image equals the CLI's for the same scene, seed and
   options: result.save() PFM and EXR against the CLI's -o PFM and --hdr EXR, compared as files
   (byte for byte: no numpy needed).
2. Overhead of a Python call against the CLI for a 1-spp render: the CLI process (median wall of
   N runs: start, load, BVH, CUDA init, upload, render, write PNG), a fresh Python process doing
   the same through the module, and warm calls on a scene loaded once (median wall per call, and
   the part of it outside the renderer's own upload and render times).
Writes python_check.json to --out and prints a summary.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import pathtracer

SCENES = [
    ("scenes/cornell_box.json", dict(width=256, height=256, spp=16, seed=5)),
    ("scenes/instanced_shapes.json", dict(width=192, height=160, spp=8, sort="queues")),
    ("scenes/cornell_glass_mirror.json", dict(width=160, height=160, spp=8, compact="off")),
    ("scenes/meshes/smooth_shapes.glb", dict(width=200, height=120, spp=8, integrator="nee")),
]


def flags(options):
    out = []
    for k, v in options.items():
        out += ["--" + k.replace("_", "-"), str(v)]
    return out


def identity(cli, out, backend):
    rows = []
    for scene_file, options in SCENES:
        stem = Path(scene_file).stem
        options = dict(options, backend=backend)
        subprocess.run([cli, scene_file, "-o", f"{out}/{stem}_cli.pfm", "--hdr",
                        f"{out}/{stem}_cli.exr", "--quiet", *flags(options)], check=True)
        result = pathtracer.render(pathtracer.Scene(scene_file), **options)
        result.save(f"{out}/{stem}_py.pfm")
        result.save(f"{out}/{stem}_py.exr")
        same = all(Path(f"{out}/{stem}_py.{e}").read_bytes() ==
                   Path(f"{out}/{stem}_cli.{e}").read_bytes() for e in ("pfm", "exr"))
        rows.append(dict(scene=scene_file, options=options, identical=same,
                         device=result.stats["device"]))
        print(f"identity {backend}: {scene_file}: {'IDENTICAL' if same else 'DIFFERENT'}")
    return rows


def wall(cmd, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t0)
    return statistics.median(times) * 1e3


def overhead(cli, out, backend, runs):
    scene_file, size = "scenes/cornell_box.json", ["--width", "512", "--height", "512"]
    cli_ms = wall([cli, scene_file, "-o", f"{out}/o.png", "--spp", "1", "--backend", backend,
                   "--quiet", *size], runs)
    subprocess.run([cli, scene_file, "-o", f"{out}/o.png", "--spp", "1", "--backend", backend,
                    "--quiet", "--stats-json", f"{out}/cli_stats.json", *size], check=True)
    cli_stats = json.loads(Path(f"{out}/cli_stats.json").read_text())
    script = ("import pathtracer; s = pathtracer.Scene('%s'); pathtracer.render(s, spp=1, "
              "backend='%s', width=512, height=512, aovs=False).save('%s/p.png')"
              % (scene_file, backend, out))
    fresh_ms = wall([sys.executable, "-c", script], runs)
    scene = pathtracer.Scene(scene_file)
    calls, inside = [], []
    for i in range(runs + 3):
        t0 = time.perf_counter()
        r = pathtracer.render(scene, spp=1, backend=backend, width=512, height=512, aovs=False)
        ms = (time.perf_counter() - t0) * 1e3
        if i >= 3:  # the first calls warm the CUDA context and allocator
            calls.append(ms)
            inside.append(r.stats["time_ms"]["upload"] + r.stats["time_ms"]["render"])
    res = dict(backend=backend, runs=runs, cli_process_ms=cli_ms,
               cli_stats_total_ms=cli_stats["time_ms"]["total"],
               cli_stats_upload_render_ms=cli_stats["time_ms"]["upload"] + cli_stats["time_ms"]["render"],
               python_process_ms=fresh_ms, python_warm_call_ms=statistics.median(calls),
               python_warm_upload_render_ms=statistics.median(inside))
    res["python_warm_overhead_ms"] = res["python_warm_call_ms"] - res["python_warm_upload_render_ms"]
    for k, v in res.items():
        print(f"overhead {backend}: {k} = {v:.2f}" if isinstance(v, float) else f"overhead: {k} = {v}")
    return res


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--cli", required=True)
    p.add_argument("--out", default="out")
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--backends", default="cuda,cpu")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    report = dict(python=sys.version, cuda_available=pathtracer.cuda_available(),
                  identity=[], overhead=[])
    for backend in a.backends.split(","):
        if backend == "cuda" and not pathtracer.cuda_available():
            print("cuda: not available here (module built without CUDA, or no GPU)")
            continue
        report["identity"] += identity(a.cli, a.out, backend)
        report["overhead"].append(overhead(a.cli, a.out, backend, a.runs))
    Path(a.out, "python_check.json").write_text(json.dumps(report, indent=2))
    bad = [r for r in report["identity"] if not r["identical"]]
    print("python_check:", "FAILED identity for " + str([r["scene"] for r in bad]) if bad else "ok")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
