#!/usr/bin/env python3
"""Error against time for the shadow-ray transmittance estimators of grid media: ratio
tracking (the default) and delta tracking (--transmittance delta).

A reference is rendered once (ratio tracking, many samples); then each estimator renders the
same scene for --seconds with --reference, the renderer logging relMSE against the reference
as it goes (reference_relmse in --stats-json). Writes a CSV of every logged point, a markdown
table of relMSE at a few times and, with matplotlib, a log-log plot.

  python3 benchmarks/media_accuracy.py --binary build/pathtracer --backend cuda \\
      --scene benchmarks/scenes/cloud_sunsky.json --size 640x360 --out out/media_accuracy
"""
import argparse
import csv
import json
import os
import subprocess


def render(args, out, extra):
    w, h = args.size.split("x")
    cmd = [args.binary, args.scene, "--backend", args.backend, "--width", w, "--height", h,
           "--quiet"] + extra + ["-o", out + ".exr", "--stats-json", out + ".json"]
    subprocess.run(cmd, check=True)
    with open(out + ".json") as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="build/pathtracer")
    ap.add_argument("--backend", default="cuda")
    ap.add_argument("--scene", default="benchmarks/scenes/cloud_sunsky.json")
    ap.add_argument("--size", default="640x360")
    ap.add_argument("--ref-spp", type=int, default=16384)
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--out", default="out/media_accuracy")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    ref = os.path.join(args.out, "reference")
    if not os.path.exists(ref + ".exr"):
        render(args, ref, ["--spp", str(args.ref_spp), "--seed", "99"])
    rows = []
    for estimator in ("ratio", "delta"):
        stats = render(args, os.path.join(args.out, estimator),
                       ["--transmittance", estimator, "--spp", "1000000", "--time-limit",
                        str(args.seconds), "--reference", ref + ".exr"])
        for point in stats["reference_relmse"]:
            rows.append({"estimator": estimator, "seconds": point["seconds"],
                         "relmse": point["relmse"],
                         "msamples_per_s": stats["msamples_per_s"]})
    with open(os.path.join(args.out, "error_vs_time.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    lines = ["| estimator | M samples/s | relMSE at 1 s | 5 s | 20 s | end |", "|---|---|---|---|---|---|"]
    for estimator in ("ratio", "delta"):
        pts = [r for r in rows if r["estimator"] == estimator]

        def at(t):
            before = [p for p in pts if p["seconds"] <= t]
            return f"{before[-1]['relmse']:.3g}" if before else "-"
        lines.append(f"| {estimator} | {pts[-1]['msamples_per_s']:.3f} | {at(1)} | {at(5)} | "
                     f"{at(20)} | {pts[-1]['relmse']:.3g} ({pts[-1]['seconds']:.0f} s) |")
    with open(os.path.join(args.out, "error_vs_time.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        for estimator in ("ratio", "delta"):
            pts = [r for r in rows if r["estimator"] == estimator]
            plt.loglog([p["seconds"] for p in pts], [p["relmse"] for p in pts], label=estimator)
        plt.xlabel("seconds")
        plt.ylabel("relMSE")
        plt.legend()
        plt.title(os.path.basename(args.scene) + ": shadow-ray transmittance")
        plt.savefig(os.path.join(args.out, "error_vs_time.png"), dpi=120)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
