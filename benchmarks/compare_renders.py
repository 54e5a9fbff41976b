#!/usr/bin/env python3
"""Render-time comparison of several pathtracer binaries (issue 28's "no regression within 3%"):
each scene rendered by each binary in turn, --rounds times interleaved (so drift on a shared or
warming machine hits every binary alike), then per scene and binary the median render time with
its range, the ratio to the first binary, the median whole-run wall time and the stages' medians.
The stats JSON of every run is kept under --out.

  python3 benchmarks/compare_renders.py --binary base=B1 --binary new=B2 --out $OUT/r
  python3 benchmarks/compare_renders.py --binary a=build/pathtracer --rounds 1 \\
      --scene "cb=scenes/cornell_box.json --width 64 --height 64 --spp 4 --backend cpu"
"""
import argparse
import glob
import json
import os
import statistics
import subprocess
import time

# The render-rate figures of issue 28 (paths relative to the project root).
DEFAULT_SCENES = [
    "pbrt=../shared/peer-scenes/pbrt_cornell.json --spp 1024",
    "cb=scenes/cornell_box.json --width 512 --height 512 --spp 64",
    "bunny=benchmarks/scenes/bunny_cornell.json --spp 1024",
    "breakfast=benchmarks/scenes/breakfast_room.json",
]


def run(binary, args, stats_path):
    start = time.perf_counter()
    subprocess.run([binary] + args + ["--quiet", "-o", "/tmp/compare_renders.png",
                                      "--stats-json", stats_path],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def summary(out, scenes, binaries):
    lines = []
    for tag, _ in scenes:
        first = None
        for name, _ in binaries:
            runs = [json.load(open(f)) for f in sorted(glob.glob(f"{out}/{tag}_{name}_*.json"))]
            walls = json.load(open(f"{out}/wall.json"))[f"{tag}_{name}"]
            renders = sorted(r["time_ms"]["render"] for r in runs)
            median = statistics.median(renders)
            first = first or median
            stages = {k: statistics.median(r["time_ms"]["stages"].get(k, 0.0) for r in runs)
                      for k, v in runs[0]["time_ms"]["stages"].items() if not isinstance(v, dict)}
            lines.append(f"{tag} {name}: render {median:.1f} ms [{renders[0]:.1f}-{renders[-1]:.1f}]"
                         f" ({median / first:.3f}x {binaries[0][0]}) wall "
                         f"{statistics.median(walls):.3f} s | " +
                         " ".join(f"{k} {v:.2f}" for k, v in stages.items() if v > 0.3))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", action="append", required=True, metavar="NAME=PATH",
                    help="a binary to compare (repeatable; the first is the reference)")
    ap.add_argument("--scene", action="append", metavar="TAG=SCENE [OPTIONS]",
                    help="a scene and its options (repeatable; default: issue 28's four)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--out", default="out/compare_renders")
    args = ap.parse_args()
    binaries = [tuple(b.split("=", 1)) for b in args.binary]
    scenes = [(s.split("=", 1)[0], s.split("=", 1)[1].split()) for s in args.scene or DEFAULT_SCENES]
    os.makedirs(args.out, exist_ok=True)
    walls = {}
    for i in range(1, args.rounds + 1):
        for name, path in binaries:
            for tag, scene_args in scenes:
                wall = run(path, scene_args, f"{args.out}/{tag}_{name}_{i}.json")
                walls.setdefault(f"{tag}_{name}", []).append(wall)
    json.dump(walls, open(f"{args.out}/wall.json", "w"))
    print(summary(args.out, scenes, binaries))


if __name__ == "__main__":
    main()
