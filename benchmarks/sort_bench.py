#!/usr/bin/env python3
"""Shading-order benchmark (issue 11): scenes x --compact x --sort (x --sort-method), N repeats.

Writes, under --out (a path prefix):
  PREFIX.csv          every run (stage times and per-queue shade times as JSON)
  PREFIX.md           medians of samples/s and speed-up over --sort off per scene and compaction;
                      the ordering cost (ms per bounce per million paths) per mode and method;
                      per-kernel times (ms per frame) for every mode, queue kernels included;
                      auto's choice and how far it lands from the best fixed mode
  PREFIX.png          chart of samples/s by scene x compaction x sort (matplotlib)

  python3 benchmarks/sort_bench.py --binary build/pathtracer --backend cuda --repeats 5 \\
      --out benchmarks/results/sort
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import plot_bars  # noqa: E402

SCENES = ["benchmarks/scenes/transmission_test.json", "benchmarks/scenes/damaged_helmet.json",
          "benchmarks/scenes/breakfast_room_materials.json", "benchmarks/scenes/material_zoo.json"]
# (compact, sort, method): the fixed modes, every ordering method once (compaction on), and
# off / queues without compaction. `auto` runs once per scene: it runs exactly the code of
# the fixed mode it picks, so its speed is that mode's median (the table shows both).
VARIANTS = [("on", "off", "auto"), ("on", "material", "counting"), ("on", "material", "radix"),
            ("on", "material", "radix32"), ("on", "queues", "counting"),
            ("off", "off", "auto"), ("off", "queues", "counting")]
AUTO = ("on", "auto", "auto")
STAGES = ["generate", "intersect", "sort", "shade", "shadow", "compact", "accumulate"]


def run_once(binary, scene, backend, variant, extra, workdir):
    compact, sort, method = variant
    stats_path = os.path.join(workdir, "stats.json")
    cmd = [binary, scene, "-o", os.path.join(workdir, "image.exr"), "--backend", backend,
           "--compact", compact, "--sort", sort, "--sort-method", method,
           "--stats-json", stats_path, "--quiet"] + extra
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    with open(stats_path) as f:
        return json.load(f), cmd


def label(row):
    return f"{row['sort']}/{row['method']}" if row["sort"] == "material" else row["sort"]


def median_by(rows, key_fn, value_fn):
    groups = {}
    for r in rows:
        groups.setdefault(key_fn(r), []).append(value_fn(r))
    return {k: statistics.median(v) for k, v in groups.items()}


def speed_table(rows):
    sps = median_by(rows, lambda r: (r["scene"], r["compact"], label(r)), lambda r: r["msamples_per_s"])
    lines = ["| scene | compact | sort | M samples/s (median) | vs off |", "|---|---|---|---|---|"]
    for (scene, compact, lab), v in sorted(sps.items()):
        off = sps.get((scene, compact, "off"))
        lines.append(f"| {scene} | {compact} | {lab} | {v:.3f} | {v / off:.3f}x |" if off else
                     f"| {scene} | {compact} | {lab} | {v:.3f} | |")
    return lines


def ordering_table(rows):
    # ms per bounce per million paths: sort stage time over the paths ordered (summed over
    # bounces), the queue-range search included.
    cost = median_by([r for r in rows if r["paths_ordered"] > 0 and r["sort"] != "auto"],
                     lambda r: (r["scene"], r["sort"], r["method_used"]),
                     lambda r: r["stages"]["sort"] / (r["paths_ordered"] / 1e6))
    lines = ["| scene | sort | method | ordering ms per bounce per M paths (median) |",
             "|---|---|---|---|"]
    lines += [f"| {s} | {m} | {meth} | {v:.3f} |" for (s, m, meth), v in sorted(cost.items())]
    return lines


def kernel_table(rows):
    lines = ["| scene | compact | sort | " + " | ".join(STAGES) + " | shade queues (ms) |",
             "|---|---|---|" + "---|" * len(STAGES) + "---|"]
    keys = sorted({(r["scene"], r["compact"], label(r)) for r in rows})
    for key in keys:
        group = [r for r in rows if (r["scene"], r["compact"], label(r)) == key]
        stage = [statistics.median(r["stages"][s] for r in group) for s in STAGES]
        queues = {}
        for r in group:
            for q, ms in r["stages"].get("shade_queues", {}).items():
                queues.setdefault(q, []).append(ms)
        qtext = ", ".join(f"{q} {statistics.median(v):.1f}" for q, v in sorted(queues.items()))
        lines.append(f"| {key[0]} | {key[1]} | {key[2]} | " +
                     " | ".join(f"{v:.1f}" for v in stage) + f" | {qtext} |")
    return lines


def auto_table(rows):
    sps = median_by(rows, lambda r: (r["scene"], r["compact"], label(r)), lambda r: r["msamples_per_s"])
    lines = ["| scene | auto chose | reason | auto (1 run) | chosen mode's median | "
             "best fixed (compaction on) | chosen / best |", "|---|---|---|---|---|---|---|"]
    for scene in sorted({r["scene"] for r in rows}):
        auto = [r for r in rows if r["scene"] == scene and r["sort"] == "auto"]
        if not auto:
            continue
        fixed = {lab: v for (s, c, lab), v in sps.items()
                 if s == scene and c == "on" and lab != "auto"}
        best = max(fixed, key=fixed.get)
        chosen = auto[0]["sort_used"]
        chosen_label = "material/counting" if chosen == "material" else chosen
        c = fixed.get(chosen_label, float("nan"))
        lines.append(f"| {scene} | {chosen} | {auto[0]['sort_reason']} | "
                     f"{auto[0]['msamples_per_s']:.3f} | {c:.3f} | {best} {fixed[best]:.3f} | "
                     f"{c / fixed[best]:.3f} |")
    return lines


def write_chart(rows, path):
    panels = []
    for scene in sorted({r["scene"] for r in rows}):
        groups = {}
        for r in rows:
            if r["scene"] == scene:
                groups.setdefault(f"c:{r['compact']}\n{label(r)}", []).append(r["msamples_per_s"])
        labels = sorted(groups)
        med = [statistics.median(groups[k]) for k in labels]
        panels.append((scene, labels, med, [m - min(groups[k]) for m, k in zip(med, labels)],
                       [max(groups[k]) - m for m, k in zip(med, labels)]))
    plot_bars(panels, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/pathtracer")
    ap.add_argument("--backend", default="cuda")
    ap.add_argument("--scene", action="append", help="default: the four sorting scenes")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default="out/sort")
    ap.add_argument("extra", nargs="*", help="pathtracer options after -- (default: 960x540, 8 spp)")
    args = ap.parse_args()
    extra = args.extra or ["--width", "960", "--height", "540", "--spp", "8"]
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scene or SCENES:
            runs = [(rep, v) for rep in range(args.repeats) for v in VARIANTS] + [(0, AUTO)]
            for rep, variant in runs:  # repeats outer: drift hits every variant alike
                if True:
                    stats, cmd = run_once(args.binary, scene, args.backend, variant, extra, tmp)
                    sort = stats["sort"]
                    rows.append({"scene": os.path.basename(scene), "compact": variant[0],
                                 "sort": variant[1], "method": variant[2], "repeat": rep,
                                 "sort_used": sort["mode"], "method_used": sort["method"] or "",
                                 "sort_reason": sort["reason"],
                                 "paths_ordered": sort["paths_ordered"],
                                 "device": stats["device"], "render_ms": stats["time_ms"]["render"],
                                 "msamples_per_s": stats["msamples_per_s"],
                                 "stages": stats["time_ms"]["stages"], "command": " ".join(cmd)})
                    print(f"{scene} {variant} rep {rep}: {stats['msamples_per_s']:.3f} MS/s",
                          flush=True)
    with open(args.out + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow(dict(r, stages=json.dumps(r["stages"])))
    text = [f"Device: {rows[0]['device']}; options: {' '.join(extra)}; medians of {args.repeats}.",
            "", "## Samples/s"] + speed_table(rows) + ["", "## Ordering cost"] + \
        ordering_table(rows) + ["", "## Per-kernel times (ms per render)"] + kernel_table(rows) + \
        ["", "## Auto"] + auto_table(rows)
    with open(args.out + ".md", "w") as f:
        f.write("\n".join(text) + "\n")
    print("\n".join(text))
    write_chart(rows, args.out + ".png")


if __name__ == "__main__":
    main()
