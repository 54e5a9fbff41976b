#!/usr/bin/env bash
# The final nearest-first build (.device/bin/pathtracer) against the session start's
# (pathtracer_base): GPU tests, memcheck, images, and renders alternating (medians of 5).
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ROOT="$PWD"; B="$ROOT/.device/bin"; S=benchmarks/scenes
ln -sfn "$ROOT/.device/shared" ../shared
mkdir -p build/test_tmp && ln -sf "$B/pathtracer" build/pathtracer
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$B" PT_SHARED_DIR="$ROOT/.device/shared"
exec > >(tee -a "$OUT/final.log") 2>&1
nvidia-smi --query-gpu=name,driver_version --format=csv
python3 $S/make_bunny_field.py > /dev/null
echo "== GPU tests"
timeout 240 "$B/pt_tests" --gtest_filter='*Gpu*:BvhWide*:Bvh/*:Instanc*:Layout*' --gtest_brief=1 2>&1 | tail -12
echo "== memcheck"
for sc in $S/bunny_cornell.json $S/bunny_field_10k.json $S/breakfast_room.json; do
  timeout 120 compute-sanitizer --tool memcheck --error-exitcode 99 "$B/pathtracer" $sc -o /tmp/m.exr \
    --width 64 --height 36 --spp 2 --backend cuda --quiet > /tmp/mc.log 2>&1
  echo "$sc: exit $? $(grep 'ERROR SUMMARY' /tmp/mc.log | tail -1)"
done
echo "== images against the session start's (320x180, 16 spp)"
for sc in breakfast_room bunny_cornell bunny_field_10k breakfast_room_bunnies; do
  for v in pathtracer_base pathtracer; do
    "$B/$v" $S/$sc.json -o /tmp/${sc}_$v.exr --width 320 --height 180 --spp 16 --backend cuda --quiet 2>/dev/null
  done
  echo "$sc: $("$B/image_compare" /tmp/${sc}_pathtracer_base.exr /tmp/${sc}_pathtracer.exr 2>&1 | tail -1)"
done
echo "== renders"
SWEEP="python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $B/pathtracer"
$SWEEP 5 $S/breakfast_room.json,$S/bunny_cornell.json,$S/breakfast_room_bunnies.json \
  "base|||$B/pathtracer_base" "nearest||" "base-binary||--bvh binary|$B/pathtracer_base" | grep -v '^[0-9] '
$SWEEP 5 $S/bunny_field_10k.json "base||--spp 64|$B/pathtracer_base" "nearest||--spp 64" | grep -v '^[0-9] '
$SWEEP 5 $S/bunny_cornell.json "base||--max-depth 0|$B/pathtracer_base" "nearest||--max-depth 0" | grep -v '^[0-9] '
$SWEEP 3 ../shared/peer-scenes/pbrt_cornell.json "base||--spp 1024|$B/pathtracer_base" "nearest||--spp 1024" | grep -v '^[0-9] '
