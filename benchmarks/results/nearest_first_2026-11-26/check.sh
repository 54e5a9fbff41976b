#!/usr/bin/env bash
# The committed build after a review (run after each): GPU tests, its images against the build
# measured in final.sh (pathtracer_tested), and the bunny and Breakfast renders alternating.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ROOT="$PWD"; B="$ROOT/.device/bin"; S=benchmarks/scenes
ln -sfn "$ROOT/.device/shared" ../shared
mkdir -p build/test_tmp && ln -sf "$B/pathtracer" build/pathtracer
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$B" PT_SHARED_DIR="$ROOT/.device/shared"
exec > >(tee -a "$OUT/check.log") 2>&1
python3 $S/make_bunny_field.py > /dev/null
timeout 300 "$B/pt_tests" --gtest_filter='*Gpu*:BvhWide*:Bvh/*:Instanc*' --gtest_brief=1 2>&1 | tail -6
for sc in breakfast_room bunny_cornell bunny_field_10k; do
  for v in pathtracer_tested pathtracer; do
    "$B/$v" $S/$sc.json -o /tmp/${sc}_$v.exr --width 320 --height 180 --spp 16 --backend cuda --quiet 2>/dev/null
  done
  echo "$sc: $("$B/image_compare" /tmp/${sc}_pathtracer_tested.exr /tmp/${sc}_pathtracer.exr 2>&1 | tail -1)"
done
python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $B/pathtracer 3 \
  $S/bunny_cornell.json,$S/breakfast_room.json "tested|||$B/pathtracer_tested" "committed||" | grep -v '^[0-9] '
