#!/usr/bin/env bash
# Issue 10's Nsight Compute before/after on the Breakfast Room: the closest-hit and shadow kernels
# of bounce 1 (launch-skip 2) in the renderer the issue was filed on (.device/old/, 1e744e1) and
# in today's binary at its default (wide, pooled) and with --bvh binary. 640x360, 4 spp.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn "$PWD/.device/shared" ../shared
NEW="$PWD/.device/bin/pathtracer"; OLD="$PWD/.device/old/pathtracer"
run() {  # name binary flags...
  local name=$1 bin=$2; shift 2
  timeout 150 ncu --clock-control none --kernel-name-base demangled \
    --kernel-name "regex:IntersectClosest|TraceShadowRays|IntersectLayout|ShadowLayout" \
    --launch-skip 2 --launch-count 2 --section SpeedOfLight --section Occupancy \
    --section LaunchStats --section MemoryWorkloadAnalysis \
    "$bin" benchmarks/scenes/breakfast_room.json -o /tmp/ncu.exr --width 640 --height 360 --spp 4 \
    --backend cuda --quiet "$@" > "$OUT/ncu_$name.txt" 2>&1
  echo "== $name: exit $?"
  grep -E "^  [a-z].*\(|Duration|Compute \(SM\) Throughput|Memory Throughput|DRAM Throughput|L1/TEX Hit|Registers Per|Theoretical Occupancy|Achieved Occupancy" \
    "$OUT/ncu_$name.txt" | sed -e 's/(unsigned int.*//' -e 's/^  void pt::ParallelFor[A-Za-z]*<[^>]*WavefrontIntegrator<pt::CudaBackend>::/  /'
}
run filed "$OLD"
run wide "$NEW"
run binary "$NEW" --bvh binary
