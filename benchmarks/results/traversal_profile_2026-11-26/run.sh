#!/usr/bin/env bash
# Issue 10, 2026-11-26: where the wide closest-hit kernel spends its instructions (ncu source
# counters per SASS line, -lineinfo build), and the layouts' ratio with a cheaper triangle
# test (--tri-test mt). From the repository root after tools/pack_device.sh.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
PT="$PWD/.device/bin/pathtracer"
[ -e ../shared ] || ln -s "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/profile.log") 2>&1
nvidia-smi --query-gpu=name,clocks.sm --format=csv
V="auto:auto:--bvh=binary,auto:auto:--bvh=wide,auto:auto:--bvh=binary --tri-test=mt,auto:auto:--bvh=wide --tri-test=mt"
timeout 200 python3 benchmarks/bench.py --binary "$PT" --backend cuda --repeats 3 --variants "$V" \
  --scene benchmarks/scenes/breakfast_room.json --scene benchmarks/scenes/bunny_cornell.json --out "$OUT/tri_mt"
for L in wide binary; do
  timeout 150 ncu --clock-control none --kernel-name-base demangled --kernel-name "regex:IntersectLayout" \
    --launch-skip 1 --launch-count 1 --section SourceCounters --section WarpStateStats \
    --metrics smsp__inst_executed.sum,smsp__thread_inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio \
    --import-source no -o "$OUT/src_$L" -f \
    "$PT" benchmarks/scenes/breakfast_room.json -o /tmp/ncu.exr --width 640 --height 360 --spp 4 \
    --backend cuda --bvh "$L" --quiet > "$OUT/ncu_run_$L.txt" 2>&1
  echo "ncu $L: exit $?"
  ncu --import "$OUT/src_$L.ncu-rep" --page details > "$OUT/details_$L.txt" 2>&1
  ncu --import "$OUT/src_$L.ncu-rep" --page source --csv --print-source sass > "$OUT/sass_$L.csv" 2>&1 \
    || ncu --import "$OUT/src_$L.ncu-rep" --page source --csv > "$OUT/sass_$L.csv" 2>&1
  echo "source page $L: exit $? $(wc -l < "$OUT/sass_$L.csv") lines"
done
ncu --help | grep -i -A2 "print-source\|--page" > "$OUT/ncu_help.txt"
