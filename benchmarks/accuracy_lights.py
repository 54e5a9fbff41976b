#!/usr/bin/env python3
"""Many lights in the accuracy study (the light BVH, issue 30): relMSE against spp and against
time of the three ways next-event estimation chooses a light,

  bvh      the light BVH: finite lights by their importance at the shading point
           (--light-sampler bvh)
  power    by power alone (--light-sampler power)
  uniform  every light alike (--light-sampler uniform)

on scenes lit by many small emitters: a generated city block at night (its streets lined
with 20,000 small downward lamps, seen from above) and the Breakfast Room hung with 10,000
fairy lights (both written by
benchmarks/scenes/make_many_lights.py), and DamagedHelmet lit only by its emissive texture
(benchmarks/scenes/damaged_helmet_emissive.json). The reference of each scene is a bvh render
of --ref-spp samples made of two halves with different seeds (their difference gives the
reference's own noise).

relMSE x time is each method's constant (from the two largest spp), so the ratio of two
constants is how many times lower one method's relMSE is at equal time (and how much sooner
it reaches a given relMSE). The issue asks bvh >= 5x better than power on the many-light
scenes. Times as in accuracy_env.py: on the CPU, process CPU seconds less a one-pixel run's
(loading, BVH and light-tree builds); on the GPU, render wall seconds.

Outputs under --out: accuracy_lights_runs.csv, accuracy_lights.md (the table) and
accuracy_lights.png (relMSE against spp and against time; needs matplotlib, else
--plot-csv draws it later from the CSV).

  /usr/bin/python3 benchmarks/accuracy_lights.py --binary build/pathtracer --backend cpu \\
      --threads 2 --out benchmarks/results                 # ~1 hour on 2 cores
  python3 benchmarks/accuracy_lights.py --binary .device/bin/pathtracer --backend cuda \\
      --size 960x540 --spps 4,16,64,256 --ref-spp 16384 --out "$OUT"
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

METHODS = {"bvh": ["--light-sampler", "bvh"], "power": ["--light-sampler", "power"],
           "uniform": ["--light-sampler", "uniform"]}
GENERATED = {"many_lights_city": ["city"], "many_lights_breakfast": ["breakfast"]}
SCENES = ["benchmarks/scenes/many_lights_city.json",
          "benchmarks/scenes/many_lights_breakfast.json",
          "benchmarks/scenes/damaged_helmet_emissive.json"]


def relmse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + REL_EPS)))


def ensure_scene(scene):
    """Writes a generated scene the first time it is asked for."""
    path = os.path.join(REPO, scene)
    name = os.path.splitext(os.path.basename(scene))[0]
    if not os.path.exists(path) and name in GENERATED:
        subprocess.run([sys.executable, os.path.join(REPO, "benchmarks/scenes/make_many_lights.py")]
                       + GENERATED[name] + [path], check=True)
    return path


def render(args, scene, spp, seed, extra, work, crop=()):
    image, stats = os.path.join(work, "img.pfm"), os.path.join(work, "stats.json")
    cmd = [args.binary, os.path.join(REPO, scene), "-o", image, "--width", str(args.w),
           "--height", str(args.h), "--spp", str(spp), "--seed", str(seed), "--backend",
           args.backend, "--stats-json", stats, "--quiet"] + extra + args.extra.split() + list(crop)
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
    return read_pfm(image), s["time_ms"]["render"] / 1e3, cpu, s


def reference(args, scene, work):
    halves = [render(args, scene, args.ref_spp // 2, seed, METHODS["bvh"], work)[0]
              for seed in (900001, 900002)]
    ref = 0.5 * (halves[0] + halves[1])
    return ref, relmse(halves[0], halves[1]) / 4.0  # the mean's own relMSE


def study(args):
    rows, refs, info = [], {}, {}
    work = tempfile.mkdtemp(prefix="accuracy_lights_")
    try:
        for scene in args.scenes:
            ensure_scene(scene)
            ref, noise = reference(args, scene, work)
            refs[scene] = noise
            print("%s: reference %d spp, own relMSE %.3g" % (scene, args.ref_spp, noise),
                  flush=True)
            for method, extra in ((m, METHODS[m]) for m in args.methods):
                startup = min(render(args, scene, 1, 1, extra, work,
                                     ["--crop", "0", "0", "1", "1"])[2] for _ in range(2))
                for spp in args.spps:
                    for seed in range(1, args.seeds + 1):
                        img, wall, cpu, s = render(args, scene, spp, seed, extra, work)
                        info[scene] = s
                        rows.append({"scene": os.path.basename(scene), "method": method,
                                     "spp": spp, "seed": seed, "wall_s": wall,
                                     "cpu_s": max(cpu - startup, 1e-3),
                                     "relmse": relmse(img, ref)})
                    print("  %-8s %5d spp: relMSE %.4g, %.3g s" % (
                        method, spp, np.mean([r["relmse"] for r in rows[-args.seeds:]]),
                        np.mean([r["wall_s"] for r in rows[-args.seeds:]])), flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return rows, refs, info


def summarize(rows, backend):
    """Per scene and method: mean relMSE and time per spp, and the constant relMSE x time."""
    clock = "cpu_s" if backend == "cpu" else "wall_s"
    out = {}
    for r in rows:
        out.setdefault((r["scene"], r["method"]), {}).setdefault(r["spp"], []).append(r)
    table = {}
    for key, by_spp in out.items():
        points = [(spp, float(np.mean([r["relmse"] for r in rs])),
                   float(np.mean([r[clock] for r in rs]))) for spp, rs in sorted(by_spp.items())]
        const = float(np.median([e * t for _, e, t in points[-2:]]))
        table[key] = {"points": points, "const": const}
    return table


def write_table(table, refs, info, args, path):
    lines = ["Light samplers, %s (%s), %dx%d, reference %d spp (bvh); relMSE is the mean over %d "
             "seeds; time in %s seconds." % (args.backend, args.label, args.w, args.h,
                                              args.ref_spp, args.seeds,
                                              "CPU" if args.backend == "cpu" else "wall"),
             "", "| scene | lights | method | " +
             " | ".join("relMSE @%d spp" % s for s in args.spps) +
             " | time @%d spp | relMSE x time | bvh's gain at equal time |" % args.spps[-1],
             "|---|---|---|" + "---|" * (len(args.spps) + 3)]
    for scene in sorted({k[0] for k in table}):
        full = [s for s in info if os.path.basename(s) == scene]
        lights = info[full[0]]["scene"]["lights"] if full else "?"
        best = table[(scene, "bvh")]["const"]
        for method in (m for m in METHODS if (scene, m) in table):
            t = table[(scene, method)]
            cells = " | ".join("%.4g" % e for _, e, _ in t["points"])
            lines.append("| %s | %s | %s | %s | %.3g | %.4g | %.1fx |" % (
                scene, lights, method, cells, t["points"][-1][2], t["const"], t["const"] / best))
    lines.append("")
    for scene, noise in sorted(refs.items()):
        lines.append("Reference noise of %s: relMSE %.3g." % (os.path.basename(scene), noise))
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
            if (scene, method) not in table:
                continue
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
    fig.suptitle("Light samplers: bvh vs power vs uniform (%s)" % args.label)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", default=os.path.join(REPO, "build/pathtracer"))
    p.add_argument("--backend", default="cpu", choices=["cpu", "cuda"])
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--size", default="160x90")
    p.add_argument("--spps", default="4,16,64")
    p.add_argument("--seeds", type=int, default=2)
    p.add_argument("--ref-spp", type=int, default=2048)
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--label", default="2 CPU threads")
    p.add_argument("--extra", default="",
                   help="options every render takes (reference too), e.g. '--sampler sobol'")
    p.add_argument("--methods", default=",".join(METHODS), help="comma-separated, of " +
                   ", ".join(METHODS))
    p.add_argument("--out", default=os.path.join(REPO, "benchmarks/results"))
    p.add_argument("--quick", action="store_true", help="32x18, spp 1 and 4, 64-spp reference")
    p.add_argument("--plot-csv", default=None,
                   help="only draw accuracy_lights.png from an earlier run's CSV")
    args = p.parse_args()
    args.w, args.h = (int(v) for v in args.size.split("x"))
    args.spps = [int(v) for v in args.spps.split(",")]
    args.scenes = args.scenes.split(",")
    args.methods = args.methods.split(",")
    if args.quick:
        args.w, args.h, args.spps, args.ref_spp, args.seeds = 32, 18, [1, 4], 64, 1
    if args.plot_csv:
        with open(args.plot_csv, newline="") as f:
            rows = [dict(r, spp=int(r["spp"]), relmse=float(r["relmse"]),
                         wall_s=float(r["wall_s"]), cpu_s=float(r["cpu_s"]))
                    for r in csv.DictReader(f)]
        plot(summarize(rows, args.backend), args, os.path.join(args.out, "accuracy_lights.png"))
        return
    os.makedirs(args.out, exist_ok=True)
    rows, refs, info = study(args)
    with open(os.path.join(args.out, "accuracy_lights_runs.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    table = summarize(rows, args.backend)
    write_table(table, refs, info, args, os.path.join(args.out, "accuracy_lights.md"))
    plot(table, args, os.path.join(args.out, "accuracy_lights.png"))


if __name__ == "__main__":
    main()
