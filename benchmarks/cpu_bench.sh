#!/usr/bin/env bash
# CPU figures for RESULTS.md: 2 threads (the CI machine's size), 3 repeats, medians. Sample
# counts are lowered from the scenes' own (rates do not depend on them) to keep it short.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${BIN:-build/pathtracer}"
OUT="${OUT:-out/cpu}"
mkdir -p "$OUT"
B="python3 benchmarks/bench.py --binary $BIN --backend cpu --repeats ${REPEATS:-3}"
$B --scene scenes/cornell_box.json --variants auto:auto --out "$OUT/cpu_cornell" -- --threads 2 --spp 16
if [ -d ../shared/assets ]; then
  $B --scene ../shared/peer-scenes/pbrt_cornell.json --variants auto:auto --out "$OUT/cpu_pbrt" \
    -- --threads 2 --spp 16
  $B --scene benchmarks/scenes/bunny_cornell.json --variants auto:auto --out "$OUT/cpu_bunny" \
    -- --threads 2 --spp 2
fi
# Specialised variants against the general one, on the CPU.
$B --scene scenes/cornell_box.json --scene scenes/cornell_glass_mirror.json \
  --variants "auto:auto:--specialize=on,auto:auto:--specialize=off" --out "$OUT/cpu_special" \
  -- --threads 2 --spp 16
