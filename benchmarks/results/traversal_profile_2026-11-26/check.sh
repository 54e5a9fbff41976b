#!/usr/bin/env bash
# Occlusion rays without postponing: the binary before (pathtracer_base) and after, alternating,
# then the GPU tests and compute-sanitizer on the new one. From the repository root after
# tools/pack_device.sh (plus the base binary copied in as .device/bin/pathtracer_base).
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
B=.device/bin; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
[ -e ../shared ] || ln -s "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/check.log") 2>&1
nvidia-smi --query-gpu=name --format=csv,noheader
V=("base||--bvh wide|$B/pathtracer_base" "new||--bvh wide" "binary||--bvh binary")
python3 $SW $B/pathtracer 3 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json,benchmarks/scenes/breakfast_room_bunnies.json "${V[@]}" | tail -12
python3 $SW $B/pathtracer 3 ../shared/peer-scenes/pbrt_cornell.json "base||--bvh wide --spp 1024|$B/pathtracer_base" "new||--bvh wide --spp 1024" "binary||--bvh binary --spp 1024" | tail -5
mkdir -p build/test_tmp && ln -sf $PWD/$B/pathtracer build/pathtracer
export PT_SOURCE_DIR="$PWD" PT_BINARY_DIR="$PWD/$B" PT_SHARED_DIR="$PWD/.device/shared"
timeout 200 $B/pt_tests --gtest_filter='*Gpu*:BvhWide*:Bvh/*:Layouts/*:Instanc*:HardLayout*:*Occlu*-GltfMaterialGpu.DamagedHelmet*' \
  --gtest_brief=1 -- 2>&1 | tail -6
for L in wide binary; do
  timeout 90 compute-sanitizer --tool memcheck --error-exitcode 99 $B/pathtracer \
    benchmarks/scenes/bunny_cornell.json -o /tmp/san.exr --width 160 --height 90 --spp 2 \
    --backend cuda --bvh $L --quiet 2>&1 | grep "ERROR SUMMARY"
done
