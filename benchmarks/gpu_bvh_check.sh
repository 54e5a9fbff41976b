#!/usr/bin/env bash
# The BVH work's GPU check (issue 10) in one device call, from the repository root after
# tools/pack_device.sh: a smoke render per layout, the --bvh binary vs wide benchmark matrix
# (medians of $REPEATS, both layouts alternating inside one run), the GPU test cases,
# compute-sanitizer memcheck of small renders in both layouts, and an ncu summary of the
# traversal kernels (IntersectLayout, ShadowLayout) per layout. Output: at most 8 files in $OUT.
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
PT="$BIN/pathtracer"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"
export PYTHONUNBUFFERED=1
R="${REPEATS:-5}"
TMP="$(mktemp -d)"
step() { echo; echo "=== $* ($(date +%T))"; }
exec > >(tee -a "$OUT/gpu_bvh.log") 2>&1

step "device"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm --format=csv
"$PT" --version
git -C "$ROOT" log -1 --format=%H 2>/dev/null || cat "$ROOT/COMMIT" 2>/dev/null

step "smoke: bunny Cornell 320x180 16 spp per layout"
for L in binary wide; do
  "$PT" benchmarks/scenes/bunny_cornell.json -o "$TMP/smoke_$L.exr" --backend cuda --bvh "$L" \
    --width 320 --height 180 --spp 16 --quiet --stats-json "$TMP/smoke_$L.json"
  echo "$L: exit $?"
done

step "benchmark matrix: --bvh binary vs wide, medians of $R"
V="auto:auto:--bvh=binary,auto:auto:--bvh=wide"
B="python3 benchmarks/bench.py --binary $PT --backend cuda --repeats $R --variants $V"
timeout 120 $B --scene ../shared/peer-scenes/pbrt_cornell.json --out "$TMP/pbrt" -- --spp 1024
timeout 120 $B --scene benchmarks/scenes/bunny_cornell.json --scene benchmarks/scenes/breakfast_room.json \
  --out "$TMP/scenes"
timeout 60 $B --scene benchmarks/scenes/bunny_cornell.json --out "$TMP/primary" -- --max-depth 0
timeout 150 $B --scene benchmarks/scenes/breakfast_room_bunnies.json --out "$TMP/large"
# Instanced: 10^4 bunnies through the two-level walk (both levels in the chosen layout).
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
timeout 150 $B --scene benchmarks/scenes/bunny_field_10k.json --out "$TMP/instanced" -- --spp 64
for part in pbrt scenes primary large instanced; do
  [ -f "$TMP/$part.md" ] && { echo "## $part"; cat "$TMP/$part.md"; echo; } >> "$OUT/bench.md"
  # The header once: the first part's file is copied whole, the others without their first line.
  if [ -f "$TMP/$part.csv" ]; then
    if [ -s "$OUT/bench.csv" ]; then tail -n +2 "$TMP/$part.csv" >> "$OUT/bench.csv"
    else cp "$TMP/$part.csv" "$OUT/bench.csv"; fi
  fi
done
python3 - "$OUT/bench.csv" <<'EOF' | tee -a "$OUT/bench.md"
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
groups = {}
for r in rows:
    key = (r["scene"], "primary" if "--max-depth 0" in r["command"] else "full")
    layout = "wide" if "--bvh=wide" in r["sort"] else "binary"
    groups.setdefault(key, {}).setdefault(layout, []).append(r)
print("\n## wide / binary (medians)\n\n| scene | kind | binary ms | wide ms | speed-up | wide M rays/s | bvh build ms (wide) |")
print("|---|---|---|---|---|---|---|")
for (scene, kind), g in sorted(groups.items()):
    if "binary" not in g or "wide" not in g: continue
    med = lambda rs, k: statistics.median(float(r[k]) for r in rs)
    b, w = med(g["binary"], "render_ms"), med(g["wide"], "render_ms")
    print(f"| {scene} | {kind} | {b:.1f} | {w:.1f} | {b / w:.2f}x | {med(g['wide'], 'mrays_per_s'):.0f} | {med(g['wide'], 'bvh_build_ms'):.0f} |")
EOF

step "GPU test cases"
timeout 150 "$BIN/pt_tests" --gtest_filter='*Gpu*' --gtest_brief=1 > "$OUT/gpu_tests.log" 2>&1
echo "pt_tests *Gpu*: exit $?"; tail -5 "$OUT/gpu_tests.log"

step "compute-sanitizer memcheck per layout"
for L in binary wide; do
  for S in scenes/cornell_box.json benchmarks/scenes/bunny_cornell.json; do
    timeout 90 compute-sanitizer --tool memcheck --error-exitcode 99 "$PT" "$S" -o "$TMP/san.exr" \
      --width 64 --height 64 --spp 2 --backend cuda --bvh "$L" --quiet >> "$OUT/sanitizer.log" 2>&1
    echo "memcheck $L $S: exit $? ($(grep 'ERROR SUMMARY' "$OUT/sanitizer.log" | tail -1))"
  done
done

step "ncu: traversal kernels per layout (bunny Cornell 960x540 4 spp)"
for L in binary wide; do
  timeout 100 ncu --clock-control none --kernel-name-base demangled \
    --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-skip 2 --launch-count 4 \
    --section SpeedOfLight --section Occupancy --section LaunchStats --section MemoryWorkloadAnalysis \
    "$PT" benchmarks/scenes/bunny_cornell.json -o "$TMP/ncu.exr" --width 960 --height 540 --spp 4 \
    --backend cuda --bvh "$L" --quiet > "$OUT/ncu_$L.txt" 2>&1
  echo "ncu $L: exit $?"
  grep -E "IntersectLayout|ShadowLayout|Memory Throughput|DRAM Throughput|Achieved Occupancy|Registers Per|Duration" \
    "$OUT/ncu_$L.txt" | sed 's/(unsigned int.*//' | head -40
done
rm -rf "$TMP"
step "done"
