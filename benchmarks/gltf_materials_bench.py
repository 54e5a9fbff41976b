#!/usr/bin/env python3
"""GPU cost of the full glTF material: samples/s and texture memory on DamagedHelmet and
TransmissionTest at 1080p, with the full metallic-roughness material and with the previous
mapping onto the plain materials (PT_GLTF_MATERIALS=legacy: conductor / plastic / dielectric /
emissive, base colour texture only). Writes a markdown table and the raw stats.

  python3 benchmarks/gltf_materials_bench.py --binary build/pathtracer --backend cuda --out out/gltf
"""
import argparse
import json
import os
import statistics
import subprocess

SCENES = ["benchmarks/scenes/damaged_helmet.json", "benchmarks/scenes/transmission_test.json"]


def run(binary, scene, backend, legacy, stats_path, extra):
    env = dict(os.environ)
    env.pop("PT_GLTF_MATERIALS", None)
    if legacy:
        env["PT_GLTF_MATERIALS"] = "legacy"
    cmd = [binary, scene, "-o", stats_path.replace(".json", ".exr"), "--backend", backend,
           "--stats-json", stats_path, "--quiet"] + extra
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    with open(stats_path) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default="build/pathtracer")
    ap.add_argument("--backend", default="cuda")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="out/gltf_materials")
    ap.add_argument("extra", nargs="*", help="extra pathtracer options (after --)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    lines = ["| scene | materials | M samples/s (median, min-max) | render ms | texture MB | "
             "peak device MB | effects |", "|---|---|---|---|---|---|---|"]
    for scene in SCENES:
        name = os.path.splitext(os.path.basename(scene))[0]
        for legacy in (False, True):
            mode = "legacy" if legacy else "full"
            stats = [run(args.binary, scene, args.backend, legacy,
                         os.path.join(args.out, f"{name}_{mode}_{r}.json"), args.extra)
                     for r in range(args.repeats)]
            rates = [s["msamples_per_s"] for s in stats]
            ms = statistics.median(s["time_ms"]["render"] for s in stats)
            s0 = stats[0]
            lines.append(f"| {name} | {mode} | {statistics.median(rates):.2f} ({min(rates):.2f}-"
                         f"{max(rates):.2f}) | {ms:.0f} | {s0['scene']['texture_bytes'] / 1e6:.1f} | "
                         f"{s0['peak_device_bytes'] / 1e6:.0f} | {' '.join(s0['scene']['effects'])} |")
            print(lines[-1], flush=True)
    with open(os.path.join(args.out, "gltf_materials.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
