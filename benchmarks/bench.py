#!/usr/bin/env python3
"""Benchmark matrix: scenes x backend x --compact x --sort, N repeats each.

Writes a CSV of every run, a markdown table of medians (with min-max spread), and, when
matplotlib is available, a PNG bar chart. Variants are compared as ratios inside one run.

  python3 benchmarks/bench.py --binary build/pathtracer --backend cpu \
      --scene benchmarks/scenes/cornell_bench.json --repeats 5 --out out/bench_cpu
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile


def run_once(binary, scene, backend, compact, sort, extra, workdir, variant_args=()):
    stats_path = os.path.join(workdir, "stats.json")
    image_path = os.path.join(workdir, "image.exr")
    cmd = [binary, scene, "-o", image_path, "--backend", backend, "--compact", compact,
           "--sort", sort, "--stats-json", stats_path, "--quiet"] + list(variant_args) + extra
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    with open(stats_path) as f:
        return json.load(f), cmd


def summarize(rows, key):
    groups = {}
    for r in rows:
        groups.setdefault((r["scene"], r["backend"], r["compact"], r["sort"]), []).append(float(r[key]))
    return {k: (statistics.median(v), min(v), max(v), len(v)) for k, v in groups.items()}


def write_markdown(rows, path):
    ms = summarize(rows, "render_ms")
    msps = summarize(rows, "msamples_per_s")
    mrps = summarize(rows, "mrays_per_s")
    lines = ["| scene | backend | compact | sort | render ms (median, min-max) | M samples/s | M rays/s | runs |",
             "|---|---|---|---|---|---|---|---|"]
    for k in sorted(ms):
        m, lo, hi, n = ms[k]
        lines.append(f"| {k[0]} | {k[1]} | {k[2]} | {k[3]} | {m:.1f} ({lo:.1f}-{hi:.1f}) | "
                     f"{msps[k][0]:.3f} | {mrps[k][0]:.2f} | {n} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return "\n".join(lines)


def plot_bars(panels, path):
    """One bar panel per (title, labels, medians, below, above), min-max error bars; PNG."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no chart", file=sys.stderr)
        return
    fig, axes = plt.subplots(1, len(panels), figsize=(4.8 * len(panels), 4.2), squeeze=False)
    for ax, (title, labels, values, below, above) in zip(axes[0], panels):
        ax.bar(range(len(values)), values, yerr=[below, above] if values else None)
        ax.set_xticks(range(len(values)))
        ax.set_xticklabels(labels, fontsize=6, rotation=60 if len(labels) > 6 else 0)
        ax.set_title(title, fontsize=9)
        ax.set_ylabel("M samples/s (median, min-max)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def write_chart(rows, path):
    med = summarize(rows, "msamples_per_s")
    panels = []
    for scene in sorted({k[0] for k in med}):
        labels, values, below, above = [], [], [], []
        for v in sorted({k[1:] for k in med}):
            if (scene,) + v in med:
                m, lo, hi, _ = med[(scene,) + v]
                labels.append(f"{v[0]}\nc:{v[1]} s:{v[2]}")
                values.append(m)
                below.append(m - lo)
                above.append(hi - m)
        panels.append((os.path.basename(scene), labels, values, below, above))
    plot_bars(panels, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/pathtracer")
    ap.add_argument("--scene", action="append", required=True)
    ap.add_argument("--backend", action="append", default=None)
    ap.add_argument("--variants", default="on:off,on:material,off:off,off:material,auto:auto",
                    help="comma-separated compact:sort[:extra flags] (extra flags space-separated)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default="out/bench")
    ap.add_argument("extra", nargs="*", help="extra pathtracer options after --")
    args = ap.parse_args()
    backends = args.backend or ["cpu"]
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scene:
            for backend in backends:
                for rep in range(args.repeats):  # repeats outermost: drift hits all variants
                    for variant in args.variants.split(","):
                        parts = variant.split(":", 2)
                        compact, sort = parts[0], parts[1]
                        flags = parts[2].split() if len(parts) > 2 else []
                        if flags:  # the table keys on (compact, sort): fold the flags into sort
                            sort_label = sort + " " + " ".join(flags)
                        else:
                            sort_label = sort
                        if True:
                            stats, cmd = run_once(args.binary, scene, backend, compact, sort,
                                                  args.extra, tmp, flags)
                            t = stats["time_ms"]
                            rows.append({
                                "scene": os.path.relpath(scene), "backend": backend,
                                "compact": compact, "sort": sort_label, "repeat": rep,
                                "specialization": stats.get("specialization", ""),
                                "device": stats.get("device", ""),
                                "render_ms": t["render"], "bvh_build_ms": t["bvh_build"],
                                "msamples_per_s": stats["msamples_per_s"],
                                "mrays_per_s": stats["mrays_per_s"],
                                "samples": stats["samples"],
                                "stages": json.dumps(t["stages"]),
                                "path_state_bytes": stats.get("path_state_bytes_per_path"),
                                "peak_device_bytes": stats.get("peak_device_bytes"),
                                "command": " ".join(cmd[:1] + [os.path.relpath(scene)] + cmd[2:3] + cmd[4:]),
                            })
                            print(f"{scene} {backend} compact={compact} sort={sort} rep={rep}: "
                                  f"{t['render']:.1f} ms, {stats['msamples_per_s']:.3f} MS/s, "
                                  f"{stats['mrays_per_s']:.2f} MR/s", flush=True)
    with open(args.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(write_markdown(rows, args.out + ".md"))
    write_chart(rows, args.out + ".png")


if __name__ == "__main__":
    main()
