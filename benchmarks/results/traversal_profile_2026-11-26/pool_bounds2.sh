# Experimental build: launch bounds 8-10 blocks for the pooled kernels (PT_EXP_MB), 8 for the
# per-ray and binary ones (PT_EXP_MB_PR).
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
for mb in 9 10; do
  PT_EXP_MB=$mb timeout 60 ncu --kernel-name-base demangled --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-count 2 --section LaunchStats \
    $P benchmarks/scenes/bunny_cornell.json -o /tmp/n.exr --width 64 --height 64 --spp 1 --backend cuda --prim-pool on --quiet 2>&1 | grep -E "Registers Per" | sed "s/^/mb $mb: /"
done
S=benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json
python3 $SW $P 3 $S "binary||--bvh binary" "binary-mb8|PT_EXP_MB_PR=8|--bvh binary" "per-ray||--prim-pool off" "per-ray-mb8|PT_EXP_MB_PR=8|--prim-pool off" "pooled-mb8|PT_EXP_MB=8|--prim-pool on" "pooled-mb9|PT_EXP_MB=9|--prim-pool on" "pooled-mb10|PT_EXP_MB=10|--prim-pool on" 2>&1 | tail -16
