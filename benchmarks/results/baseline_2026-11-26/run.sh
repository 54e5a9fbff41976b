#!/usr/bin/env bash
# Issue 10's ratios against the renderer the issue was filed on (1e744e1, built with today's
# nvcc for sm_90, carried as .device/old/) and against today's --bvh binary, alternating in one
# call; then the SBVH build in both layouts. Run from the repository root after
# tools/pack_device.sh and the old binary copied to .device/old/.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/run.log") 2>&1
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv
NEW="$PWD/.device/bin/pathtracer"; OLD="$PWD/.device/old/pathtracer"
SWEEP="python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $NEW"
V=("filed-1e744e1|||$OLD" "binary||--bvh binary" "wide||")
$SWEEP 5 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json "${V[@]}"
$SWEEP 5 ../shared/peer-scenes/pbrt_cornell.json "filed-1e744e1||--spp 1024|$OLD" \
  "binary||--spp 1024 --bvh binary" "wide||--spp 1024"
$SWEEP 5 benchmarks/scenes/bunny_cornell.json "filed-1e744e1||--max-depth 0|$OLD" \
  "binary||--max-depth 0 --bvh binary" "wide||--max-depth 0"
$SWEEP 3 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json \
  "binary-sbvh||--bvh binary --bvh-build sbvh" "wide-sbvh||--bvh wide --bvh-build sbvh"
