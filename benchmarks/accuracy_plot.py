#!/usr/bin/env python3
"""Charts of benchmarks/accuracy.py's CSV: per scene, error (relMSE, cli.md's definition)
against render time on log-log axes, one line per configuration, with the 1e-2 and 1e-3
levels marked; a second panel shows relMSE against spp with the slope -1 (sqrt(relMSE) ~
spp^-0.5) for reference. Writes benchmarks/results/accuracy_<scene>.png.

  python3 benchmarks/accuracy_plot.py --csv OUT/accuracy_runs.csv [--out-dir benchmarks/results]
"""
import argparse
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Line styles by study group; colours cycle within the figure.
GROUP_STYLE = {"integrator": "-", "adaptive": "--", "russian roulette": "-.",
               "max depth": ":", "light paths": (0, (5, 1)), "compaction": (0, (1, 1)),
               "sorting": (0, (3, 1, 1, 1)), "film": (0, (5, 2, 1, 2))}
MARKERS = "osD^v<>ph*XP+x"


def mean(v):
    return sum(v) / len(v)


def load(path):
    """{scene: {config: (group, [(spp, mean time, mean relMSE, n)])}} from the study rows."""
    acc = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    groups = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["part"] != "study" or r["status"] != "ok" or not r["relmse"]:
                continue
            acc[r["scene"]][r["config"]][int(r["spp"])].append(
                (float(r["render_s"]), float(r["relmse"])))
            groups[(r["scene"], r["config"])] = r["group"]
    out = {}
    for scene, cfgs in acc.items():
        out[scene] = {}
        for cfg, by in cfgs.items():
            pts = [(spp, mean([t for t, _ in v]), mean([e for _, e in v]), len(v))
                   for spp, v in sorted(by.items())]
            out[scene][cfg] = (groups[(scene, cfg)], pts)
    return out


def plot_scene(scene, cfgs, out_path, title_extra=""):
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(15, 7.5), gridspec_kw={"width_ratios": [3, 2]})
    cmap = plt.get_cmap("tab20")
    order = sorted(cfgs, key=lambda c: (list(GROUP_STYLE).index(cfgs[c][0])
                                        if cfgs[c][0] in GROUP_STYLE else 99, c))
    for i, cfg in enumerate(order):
        group, pts = cfgs[cfg]
        pts = [p for p in pts if p[1] > 0 and p[2] > 0]
        if not pts:
            continue
        style = dict(color=cmap(i % 20), linestyle=GROUP_STYLE.get(group, "-"),
                     marker=MARKERS[i % len(MARKERS)], markersize=4, linewidth=1.4)
        if cfg == "mis":  # the baseline (= rr 3, depth 8, compact on, sort off, film float)
            style.update(color="black", linewidth=2.4, zorder=5)
            cfg = "mis (baseline)"
        label = "%s (%s)" % (cfg, group) if group not in ("integrator",) else cfg
        ax.plot([p[1] for p in pts], [p[2] for p in pts], label=label, **style)
        ax2.plot([p[0] for p in pts], [p[2] for p in pts], **style)
    for ax_ in (ax, ax2):
        ax_.set_xscale("log")
        ax_.set_yscale("log")
        ax_.grid(True, which="both", alpha=0.25)
        for lvl in (1e-2, 1e-3):
            ax_.axhline(lvl, color="k", linewidth=0.9, linestyle="--", alpha=0.6)
    xmin = ax.get_xlim()[0]
    for lvl in (1e-2, 1e-3):
        ax.text(xmin, lvl, " relMSE %g" % lvl, va="bottom", ha="left", fontsize=8)
    # Slope -1 in relMSE (sqrt(relMSE) ~ spp^-0.5) through the baseline's first point.
    base = cfgs.get("mis")
    if base and base[1]:
        s0, _, e0, _ = base[1][0]
        s1 = base[1][-1][0]
        ax2.plot([s0, s1], [e0, e0 * s0 / s1], color="grey", linewidth=3, alpha=0.35,
                 label="slope -1 (unbiased)")
        ax2.legend(fontsize=8, loc="lower left")
    ax.set_xlabel("render time, s (time_ms.render; mean over seeds)")
    ax.set_ylabel("relMSE vs reference (mean over seeds)")
    ax2.set_xlabel("samples per pixel")
    ax2.set_ylabel("relMSE")
    ax.set_title("%s: error against time%s" % (scene, title_extra))
    ax2.set_title("error against spp")
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, frameon=False)
    fig.tight_layout(rect=[0, 0.13, 1, 1])
    fig.savefig(out_path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", default=os.path.join(REPO, "benchmarks/results/accuracy_runs.csv"),
                    help="accuracy_runs.csv written by accuracy.py")
    ap.add_argument("--out-dir", default=os.path.join(REPO, "benchmarks/results"))
    ap.add_argument("--title", default="", help="text added to each title (device, date)")
    a = ap.parse_args(argv)
    data = load(a.csv)
    if not data:
        print("no study rows in %s" % a.csv, file=sys.stderr)
        return 1
    os.makedirs(a.out_dir, exist_ok=True)
    for scene, cfgs in sorted(data.items()):
        out = os.path.join(a.out_dir, "accuracy_%s.png" % scene)
        plot_scene(scene, cfgs, out, (" (%s)" % a.title) if a.title else "")
        print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
