# Pooled leaf tests in kernels of their own (--prim-pool), and the few-entries fallback
# (PT_EXP_POOLMIN: a step with at most that many entries tests per lane), against the per-ray walk.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
for sc in benchmarks/scenes/bunny_cornell.json ../shared/peer-scenes/pbrt_cornell.json; do
  for m in off on; do timeout 60 $P $sc -o /tmp/p$m.exr --backend cuda --width 320 --height 180 --spp 16 --quiet --prim-pool $m 2>&1 | grep -v "effects\|wrote\|spp in"; done
  echo "$sc: $(.device/bin/image_compare /tmp/poff.exr /tmp/pon.exr | tr '\n' ' ')"
done
timeout 60 ncu --kernel-name-base demangled --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-skip 0 --launch-count 4 --section LaunchStats \
  $P benchmarks/scenes/bunny_cornell.json -o /tmp/n.exr --width 64 --height 64 --spp 1 --backend cuda --prim-pool on --quiet 2>&1 | grep -E "Layout<|Registers Per|Static Shared" | sed 's/(unsigned int.*//; s/.*WavefrontIntegrator<CudaBackend>:://'
S=benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json,benchmarks/scenes/breakfast_room_bunnies.json
python3 $SW $P 3 $S "binary||--bvh binary" "wide||--bvh wide --prim-pool off" "pool||--bvh wide --prim-pool on" "pool8|PT_EXP_POOLMIN=8|--bvh wide --prim-pool on" "pool24|PT_EXP_POOLMIN=24|--bvh wide --prim-pool on" 2>&1 | tail -17
python3 $SW $P 3 ../shared/peer-scenes/pbrt_cornell.json "binary||--bvh binary --spp 1024" "wide||--bvh wide --spp 1024 --prim-pool off" "pool||--bvh wide --spp 1024 --prim-pool on" "pool8|PT_EXP_POOLMIN=8|--bvh wide --spp 1024 --prim-pool on" "pool24|PT_EXP_POOLMIN=24|--bvh wide --spp 1024 --prim-pool on" 2>&1 | tail -7
