#!/usr/bin/env python3
"""Tables from the --stats-json files of benchmarks/mpi_gpu_check.sh: per scene and GPU count,
the median render time, efficiency T1 / (N * TN), and where the time goes.

    python3 benchmarks/mpi_summary.py OUT_DIR

Files are named SCENE_NgpuR.json (run R on N GPUs), SCENE_1gpu_chunks.json and
SCENE_Ngpu_lanes1.json. One GPU's time is the plain render's time_ms.render (the render loop,
as every other benchmark here reports it); N GPUs' is mpi.render_ms, the wall time from the
common start of rendering to the reduced film on rank 0, so it includes the reduction. Start-up
(MPI, scene load, BVH, sessions and upload) is reported apart: it does not shrink with more GPUs.
"""
import json
import re
import statistics
import sys
from pathlib import Path


def wall_times(out):
    """Seconds each run took from its command's start to its end (start-up included)."""
    path = Path(out) / "wall.csv"
    if not path.exists():
        return {}
    rows = (line.split(",") for line in path.read_text().split())
    return {name: float(seconds) for name, seconds in rows}


def load(out):
    runs = {}
    extra = {}
    for path in sorted(Path(out).glob("*.json")):
        m = re.fullmatch(r"(.+)_(\d+)gpu_(\d+)", path.stem)
        doc = json.loads(path.read_text())
        if m:
            runs.setdefault((m.group(1), int(m.group(2))), []).append(doc)
        else:
            extra[path.stem] = doc
    return runs, extra


def render_ms(doc):
    return doc["mpi"]["render_ms"] if "mpi" in doc else doc["time_ms"]["render"]


def startup_ms(doc):
    t = doc["time_ms"]
    if "mpi" in doc:
        s = doc["mpi"]["startup_ms"]
        return s["mpi_init"] + t["load"] + t["bvh_build"] + s["lanes"]
    return t["load"] + t["bvh_build"] + t["upload"]


def median_run(docs):
    times = sorted(render_ms(d) for d in docs)
    mid = times[len(times) // 2]
    return next(d for d in docs if render_ms(d) == mid)


def main(out):
    runs, extra = load(out)
    walls = wall_times(out)
    scenes = sorted({s for s, _ in runs})
    print("## Render time, 1 GPU against N GPUs (medians; min-max)\n")
    print("| scene | GPUs | render s | efficiency | reduction ms | start-up s | Msamples/s | "
          "load balance | whole run s | efficiency of whole runs |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        counts = sorted(n for s, n in runs if s == scene)
        base = statistics.median(render_ms(d) for d in runs[(scene, 1)]) if 1 in counts else None
        for n in counts:
            docs = runs[(scene, n)]
            times = [render_ms(d) / 1e3 for d in docs]
            t = statistics.median(times)
            eff = f"{base / 1e3 / (n * t):.3f}" if base else "-"
            red = statistics.median(d["mpi"]["reduction_ms"] for d in docs) if n > 1 else 0.0
            lb = statistics.median(d["mpi"]["load_balance"] for d in docs) if n > 1 else 1.0
            rate = statistics.median(d["samples"] / render_ms(d) / 1e3 for d in docs)
            start = statistics.median(startup_ms(d) for d in docs) / 1e3
            wall = [v for k, v in walls.items() if k.startswith(f"{scene}_{n}gpu_")]
            wall1 = [v for k, v in walls.items() if k.startswith(f"{scene}_1gpu_")]
            w = f"{statistics.median(wall):.2f}" if wall else "-"
            weff = (f"{statistics.median(wall1) / (n * statistics.median(wall)):.3f}"
                    if wall and wall1 else "-")
            print(f"| {scene} | {n} | {t:.3f} ({min(times):.3f}-{max(times):.3f}) | {eff} | "
                  f"{red:.1f} | {start:.2f} | {rate:.1f} | {lb:.3f} | {w} | {weff} |")
    print("\n## Where the time goes on each rank (median run)\n")
    print("| scene | GPUs | rank | device | lanes | leaves | finished s | render (lane sum) s | "
          "film download s | waiting s | merging s | hand-over s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for (scene, n), docs in sorted(runs.items()):
        if n == 1:
            continue
        for r in median_run(docs)["mpi"]["per_rank"]:
            print(f"| {scene} | {n} | {r['rank']} | {r['device']} | {r['lanes']} | {r['leaves']} | "
                  f"{r['finished_ms'] / 1e3:.3f} | {r['render_ms'] / 1e3:.3f} | "
                  f"{r['save_ms'] / 1e3:.3f} | {r['wait_ms'] / 1e3:.3f} | "
                  f"{r['merge_ms'] / 1e3:.3f} | {r['send_ms'] / 1e3:.3f} |")
    if extra:
        print("\n## Other runs\n")
        for name, doc in sorted(extra.items()):
            print(f"- {name}: render {render_ms(doc) / 1e3:.3f} s, "
                  f"{doc['msamples_per_s']:.1f} Msamples/s"
                  + (f", reduction {doc['mpi']['reduction_ms']:.1f} ms" if "mpi" in doc else ""))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out")
