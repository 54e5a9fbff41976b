#!/usr/bin/env bash
# GPU check of instancing, run on the GPU machine from the repository root after
# tools/pack_device.sh (the device tool carries .device/): the instancing GPU test, the
# instanced scene under compute-sanitizer, and the 10^4-bunny field rendered in both layouts
# (time, peak RSS, peak device memory from the stats), and instance moves in the live preview.
# Output goes to $OUT (or out/).
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"

echo "=== instancing GPU tests"
"$BIN/pt_tests" --gtest_filter='Instancing*:BackendAgreementGpu.EveryProjectSceneAgreesWithCpu' \
  --gtest_brief=1 2>&1 | tee "$OUT/instancing_gpu_tests.log" | tail -20

echo "=== compute-sanitizer memcheck, scenes/instanced_shapes.json 64x64 4 spp, both layouts"
for bvh in binary wide; do
  compute-sanitizer --tool memcheck --error-exitcode 99 "$BIN/pathtracer" \
    scenes/instanced_shapes.json -o "$OUT/san_$bvh.exr" --width 64 --height 64 --spp 4 \
    --backend cuda --bvh "$bvh" --quiet > "$OUT/sanitizer_$bvh.log" 2>&1
  echo "$bvh: exit $? ($(grep -E 'ERROR SUMMARY' "$OUT/sanitizer_$bvh.log" | tail -1))"
done

echo "=== 10^4 bunnies (694M placed triangles), 640x360 16 spp"
python3 benchmarks/scenes/make_bunny_field.py
for bvh in binary wide; do
  /usr/bin/time -f "$bvh: peak RSS %M KiB, wall %e s" "$BIN/pathtracer" \
    benchmarks/scenes/bunny_field_10k.json -o "$OUT/bunny_field_$bvh.png" --backend cuda \
    --bvh "$bvh" --stats-json "$OUT/bunny_field_$bvh.json" 2>&1 | tail -3
done
"$BIN/instance_bench" benchmarks/scenes/bunny_field_10k.json --bvh wide --moves 1 --repeats 20

echo "=== live preview, 1080p: moving a bunny (top-level rebuild) against moving the floor (scene rebuild)"
for object in 500 0; do
  python3 benchmarks/serve_latency.py --pathtracer "$BIN/pathtracer" --backend cuda \
    --scene benchmarks/scenes/bunny_field_10k.json --width 1920 --height 1080 --edits 20 \
    --seconds 3 --move-object "$object" --json "$OUT/serve_move_object_$object.json"
done
"$BIN/pt_tests" --gtest_filter='ServeGpu.*:ServeInstances.*' --gtest_brief=1 2>&1 | tail -5
