#!/usr/bin/env python3
"""Environment-map sampling in the accuracy study: relMSE at equal spp and at equal time of
three ways to light a scene by a sun-and-sky map (a Preetham sky with the sun's disk painted
into its texels, written by make_sky):

  importance  MIS of BSDF sampling and next-event estimation that samples the map by
              luminance x solid angle (the default)
  uniform     the same MIS, next-event estimation sampling the sphere uniformly
              (--env-sampling uniform)
  bsdf        BSDF sampling alone (--integrator bsdf): escaped rays find the map

on a diffuse and a glossy scene (benchmarks/scenes/env_diffuse.json, env_glossy.json).
The reference of each scene is an importance render of --ref-spp samples made of two halves
with different seeds; their difference gives the reference's own noise.

Each method's relMSE falls as 1/spp (and so as 1/time), so the product relMSE x time is the
method's constant: the time to reach any relMSE r is that constant / r, and the ratio of two
methods' constants is how much sooner one reaches a given error (the speed-up reported).

Outputs under --out: accuracy_env_runs.csv (every run), accuracy_env.md (the table),
accuracy_env.png (relMSE against spp and against time, when matplotlib is present; else
--plot-csv draws it later from the CSV where matplotlib is).
Times: render_ms from --stats-json (wall clock, loading excluded), and, on the CPU, the
process's CPU time (user + system) less that of a one-pixel one-sample run of the same
scene and flags (loading the map, building tables and BVH), which other work on a shared
machine disturbs far less than wall time; the equal-time figures use those CPU seconds on
the CPU backend and wall seconds on the GPU.

  /usr/bin/python3 benchmarks/accuracy_env.py --binary build/pathtracer --backend cpu \\
      --threads 2 --out benchmarks/results            # ~15 minutes on 2 cores
  python3 benchmarks/accuracy_env.py --binary .device/bin/pathtracer --backend cuda \\
      --size 640x480 --spps 16,64,256,1024 --ref-spp 65536 --out "$OUT"
"""
import argparse
import csv
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_lib import REL_EPS, REPO, read_pfm  # noqa: E402

METHODS = {"importance": [], "uniform": ["--env-sampling", "uniform"],
           "bsdf": ["--integrator", "bsdf"]}
SCENES = ["benchmarks/scenes/env_diffuse.json", "benchmarks/scenes/env_glossy.json"]
MAP = "benchmarks/scenes/maps/sunsky_2048.exr"
MAP_ARGS = ["--elevation", "35", "--azimuth", "60", "--turbidity", "3", "--width", "2048",
            "--strength", "0.03"]


def relmse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + REL_EPS)))


def ensure_map(make_sky):
    path = os.path.join(REPO, MAP)
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        subprocess.run([make_sky, "-o", path] + MAP_ARGS, check=True)
    return path


def render(args, scene, spp, seed, extra, work, crop=()):
    image, stats = os.path.join(work, "img.pfm"), os.path.join(work, "stats.json")
    cmd = [args.binary, os.path.join(REPO, scene), "-o", image, "--width", str(args.w),
           "--height", str(args.h), "--spp", str(spp), "--seed", str(seed), "--backend",
           args.backend, "--stats-json", stats, "--quiet"] + extra + list(crop)
    if args.backend == "cpu":
        cmd += ["--threads", str(args.threads)]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise RuntimeError("%s failed: %s" % (" ".join(cmd), proc.stderr[-2000:]))
    with open(stats) as f:
        s = json.load(f)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return read_pfm(image), s["time_ms"]["render"] / 1e3, cpu


def reference(args, scene, work):
    halves = [render(args, scene, args.ref_spp // 2, seed, [], work)[0]
              for seed in (900001, 900002)]
    ref = 0.5 * (halves[0] + halves[1])
    # relMSE(h1, h2) ~ 2x each half's, 4x the mean's: the reference's own error.
    return ref, relmse(halves[0], halves[1]) / 4.0


def study(args):
    rows, refs = [], {}
    work = tempfile.mkdtemp(prefix="accuracy_env_")
    try:
        return study_in(args, work, rows, refs)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def study_in(args, work, rows, refs):
    for scene in args.scenes:
        ref, noise = reference(args, scene, work)
        refs[scene] = noise
        print("%s: reference %d spp, own relMSE %.3g" % (scene, args.ref_spp, noise), flush=True)
        for method, extra in METHODS.items():
            startup = min(render(args, scene, 1, 1, extra, work, ["--crop", "0", "0", "1", "1"])[2]
                          for _ in range(3))
            for spp in args.spps:
                for seed in range(1, args.seeds + 1):
                    img, wall, cpu = render(args, scene, spp, seed, extra, work)
                    rows.append({"scene": os.path.basename(scene), "method": method, "spp": spp,
                                 "seed": seed, "wall_s": wall, "cpu_s": max(cpu - startup, 1e-3),
                                 "relmse": relmse(img, ref)})
                print("  %-10s %5d spp: relMSE %.4g" % (
                    method, spp, np.mean([r["relmse"] for r in rows[-args.seeds:]])), flush=True)
    return rows, refs


def summarize(rows, refs, backend):
    """Per scene and method: mean relMSE and time at each spp, and relMSE x time."""
    clock = "cpu_s" if backend == "cpu" else "wall_s"
    out = {}
    for r in rows:
        out.setdefault((r["scene"], r["method"]), {}).setdefault(r["spp"], []).append(r)
    table = {}
    for key, by_spp in out.items():
        points = []
        for spp, rs in sorted(by_spp.items()):
            e = float(np.mean([r["relmse"] for r in rs]))
            t = float(np.mean([r[clock] for r in rs]))
            points.append((spp, e, t))
        # The constant from the two largest spp counts (least start-up time in t).
        const = float(np.median([e * t for _, e, t in points[-2:]]))
        table[key] = {"points": points, "const": const}
    return table


def write_table(table, refs, args, path):
    lines = ["Environment sampling, %s (%s), %dx%d, reference %d spp; relMSE is the mean over "
             "%d seeds; time in %s seconds." % (args.backend, args.label, args.w, args.h,
                                                 args.ref_spp, args.seeds,
                                                 "CPU" if args.backend == "cpu" else "wall"),
             "", "| scene | method | " + " | ".join("relMSE @%d spp" % s for s in args.spps) +
             " | relMSE x time | time to a given relMSE vs importance |",
             "|---|---|" + "---|" * (len(args.spps) + 2)]
    for scene in sorted({k[0] for k in table}):
        base = table[(scene, "importance")]["const"]
        for method in METHODS:
            t = table[(scene, method)]
            cells = " | ".join("%.4g" % e for _, e, _ in t["points"])
            lines.append("| %s | %s | %s | %.4g | %.1fx |" % (scene, method, cells, t["const"],
                                                               t["const"] / base))
    lines.append("")
    for scene, noise in sorted(refs.items()):
        lines.append("Reference noise of %s: relMSE %.3g." % (os.path.basename(scene), noise))
    for scene in sorted({k[0] for k in table}):
        speed = table[(scene, "bsdf")]["const"] / table[(scene, "importance")]["const"]
        lines.append("%s: importance sampling reaches a given relMSE %.1fx sooner than BSDF "
                     "sampling alone (uniform: %.1fx)." % (
                         scene, speed, table[(scene, "bsdf")]["const"] /
                         table[(scene, "uniform")]["const"]))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def plot(table, args, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no chart", file=sys.stderr)
        return
    scenes = sorted({k[0] for k in table})
    fig, axes = plt.subplots(len(scenes), 2, figsize=(10, 4 * len(scenes)), squeeze=False)
    unit = "CPU s" if args.backend == "cpu" else "s"
    for row, scene in zip(axes, scenes):
        for method, style in zip(METHODS, ("o-", "s--", "^:")):
            pts = table[(scene, method)]["points"]
            row[0].loglog([p[0] for p in pts], [p[1] for p in pts], style, label=method)
            row[1].loglog([p[2] for p in pts], [p[1] for p in pts], style, label=method)
        row[0].set_xlabel("samples per pixel")
        row[1].set_xlabel("render time (%s)" % unit)
        for ax, what in zip(row, ("equal spp", "equal time")):
            ax.set_ylabel("relMSE")
            ax.set_title("%s: %s" % (scene, what), fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8)
    fig.suptitle("Sun-and-sky map: importance vs uniform vs BSDF-only (%s)" % args.label)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build/pathtracer"))
    p.add_argument("--make-sky", default=None, help="default: make_sky beside --binary")
    p.add_argument("--backend", default="cpu", choices=["cpu", "cuda"])
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", default="96x72")
    p.add_argument("--spps", default="4,16,64,256")
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--ref-spp", type=int, default=8192)
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--label", default="2 CPU threads")
    p.add_argument("--out", default=os.path.join(REPO, "benchmarks/results"))
    p.add_argument("--quick", action="store_true", help="16x12, spp 1 and 4, 256-spp reference")
    p.add_argument("--plot-csv", default=None,
                   help="only draw accuracy_env.png from an earlier run's accuracy_env_runs.csv")
    args = p.parse_args()
    args.w, args.h = (int(v) for v in args.size.split("x"))
    args.spps = [int(v) for v in args.spps.split(",")]
    args.scenes = args.scenes.split(",")
    if args.quick:
        args.w, args.h, args.spps, args.ref_spp, args.seeds = 16, 12, [1, 4], 256, 2
    if args.plot_csv:
        with open(args.plot_csv, newline="") as f:
            rows = [dict(r, spp=int(r["spp"]), relmse=float(r["relmse"]), wall_s=float(r["wall_s"]),
                         cpu_s=float(r["cpu_s"])) for r in csv.DictReader(f)]
        plot(summarize(rows, {}, args.backend), args, os.path.join(args.out, "accuracy_env.png"))
        return
    ensure_map(args.make_sky or os.path.join(os.path.dirname(args.binary), "make_sky"))
    os.makedirs(args.out, exist_ok=True)
    rows, refs = study(args)
    with open(os.path.join(args.out, "accuracy_env_runs.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    table = summarize(rows, refs, args.backend)
    write_table(table, refs, args, os.path.join(args.out, "accuracy_env.md"))
    plot(table, args, os.path.join(args.out, "accuracy_env.png"))


if __name__ == "__main__":
    main()
