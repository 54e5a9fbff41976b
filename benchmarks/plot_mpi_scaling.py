#!/usr/bin/env python3
"""Efficiency against GPU count as an SVG chart (no plotting library needed): the measured
points of an mpi_gpu_check.sh summary.md, and the cost model's curve for the same frames.

    python3 benchmarks/plot_mpi_scaling.py SUMMARY.md OUT.svg [--spp 4096] [--max-gpus 8]
"""
import argparse
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mpi_cost_model as cm  # noqa: E402

SCENES = {"bunny": (1920, 1080, cm.BUNNY_RATE, "#c0392b"),
          "breakfast": (1280, 720, cm.BREAKFAST_RATE, "#2471a3")}
W, H, L, R, T, B = 660, 400, 70, 170, 30, 50  # size and margins (left, right, top, bottom)
LO = 0.8  # the efficiency axis runs from LO to 1.05


def measured(summary):
    points = {}
    for line in Path(summary).read_text().splitlines():
        m = re.match(r"\| (\w+) \| (\d+) \| [\d.]+ \([^)]*\) \| ([\d.]+) \|", line)
        if m:
            points.setdefault(m.group(1), []).append((int(m.group(2)), float(m.group(3))))
    return points


def chart(points, spp, max_gpus):
    def x(n):
        return L + (n - 1) / (max_gpus - 1) * (W - L - R)

    def y(e):
        return T + (1.05 - e) / (1.05 - LO) * (H - T - B)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           'font-family="sans-serif" font-size="12">', f'<rect width="{W}" height="{H}" fill="white"/>']
    for e in (0.8, 0.85, 0.9, 0.95, 1.0):
        dash = ' stroke-dasharray="4 3"' if e in (0.9, 0.95) else ""
        out.append(f'<line x1="{L}" x2="{W - R}" y1="{y(e):.1f}" y2="{y(e):.1f}" stroke="#ccc"{dash}/>')
        out.append(f'<text x="{L - 8}" y="{y(e) + 4:.1f}" text-anchor="end">{e:.2f}</text>')
    for n in range(1, max_gpus + 1):
        out.append(f'<text x="{x(n):.1f}" y="{H - B + 18}" text-anchor="middle">{n}</text>')
    out.append(f'<text x="{(L + W - R) / 2}" y="{H - 10}" text-anchor="middle">GPUs</text>')
    out.append(f'<text x="16" y="{(T + H - B) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 16 {(T + H - B) / 2})">efficiency T1 / (N TN)</text>')
    a = argparse.Namespace(lanes=2, chunks=32, gpus_per_host=8, save_ns=cm.SAVE_NS_PER_PIXEL,
                           merge_ns=cm.MERGE_NS_PER_PIXEL, host_link=cm.HOST_LINK, ib=25e9)
    row = 0
    for name, (w, h, rate, colour) in SCENES.items():
        curve = []
        # Powers of two: the counts whose leaves divide evenly (others leave a ragged last round).
        for n in (k for k in (1, 2, 4, 8, 16) if k <= max_gpus):
            t1, tn, _ = cm.model(a, n, w * h, spp, rate, 32 if n > 1 else 1)
            curve.append(f"{x(n):.1f},{y(t1 / (n * tn)):.1f}")
        out.append(f'<polyline points="{" ".join(curve)}" fill="none" stroke="{colour}" '
                   'stroke-dasharray="6 4"/>')
        for n, e in points.get(name, []):
            out.append(f'<circle cx="{x(n):.1f}" cy="{y(min(e, 1.05)):.1f}" r="5" fill="{colour}"/>')
        ly = T + 20 + 40 * row
        out.append(f'<circle cx="{W - R + 18}" cy="{ly}" r="5" fill="{colour}"/>')
        out.append(f'<text x="{W - R + 28}" y="{ly + 4}">{name} measured</text>')
        out.append(f'<line x1="{W - R + 10}" x2="{W - R + 26}" y1="{ly + 18}" y2="{ly + 18}" '
                   f'stroke="{colour}" stroke-dasharray="6 4"/>')
        out.append(f'<text x="{W - R + 28}" y="{ly + 22}">{name} model</text>')
        row += 1
    out.append("</svg>")
    return "\n".join(out)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("summary")
    p.add_argument("out")
    p.add_argument("--spp", type=int, default=4096)
    p.add_argument("--max-gpus", type=int, default=8)
    a = p.parse_args()
    Path(a.out).write_text(chart(measured(a.summary), a.spp, a.max_gpus) + "\n")


if __name__ == "__main__":
    main()
