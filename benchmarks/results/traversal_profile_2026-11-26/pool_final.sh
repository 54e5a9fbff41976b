# --prim-pool on the final binary: pooled vs per-ray wide walk vs binary (alternating, medians
# of 3), and compute-sanitizer's memcheck, racecheck and synccheck on pooled renders of both
# kernel variants (without and with the hit test).
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
exec > >(tee -a "$OUT/pool_final.log") 2>&1
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
nvidia-smi --query-gpu=name --format=csv,noheader; git log -1 --format=%H 2>/dev/null
for tool in memcheck racecheck synccheck; do
  for t in watertight box-clamped; do
    timeout 120 compute-sanitizer --tool $tool $P benchmarks/scenes/bunny_cornell.json -o /tmp/s.exr --backend cuda \
      --width 96 --height 64 --spp 2 --prim-pool on --tri-test $t --quiet 2>&1 | grep -E "ERROR SUMMARY|RACECHECK SUMMARY" | sed "s/^/$tool $t: /"
  done
done
S=benchmarks/scenes/breakfast_room.json,benchmarks/scenes/breakfast_room_bunnies.json,benchmarks/scenes/bunny_cornell.json
python3 $SW $P 3 $S "binary||--bvh binary" "per-ray||--bvh wide --prim-pool off" "pooled||--bvh wide --prim-pool on" 2>&1 | tail -11
python3 $SW $P 3 ../shared/peer-scenes/pbrt_cornell.json "binary||--bvh binary --spp 1024" "per-ray||--bvh wide --spp 1024 --prim-pool off" "pooled||--bvh wide --spp 1024 --prim-pool on" 2>&1 | tail -5
mkdir -p build/test_tmp && ln -sf $PWD/.device/bin/pathtracer build/pathtracer
export PT_SOURCE_DIR="$PWD" PT_BINARY_DIR="$PWD/.device/bin" PT_SHARED_DIR="$PWD/.device/shared"
timeout 200 .device/bin/pt_tests --gtest_filter='*Gpu*:BvhWide*:Bvh/*:Layouts/*:Instanc*:HardLayout*:PrimPool*-GltfMaterialGpu.DamagedHelmet*' --gtest_brief=1 2>&1 | tail -6
