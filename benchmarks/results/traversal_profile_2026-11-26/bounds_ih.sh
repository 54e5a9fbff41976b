# Experimental build: launch bounds (PT_EXP_MB_IH = 7 or 8 blocks) for the instanced and
# hit-test traversal variants, which the final build leaves unbounded.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for mb in 0 7 8; do
  PT_EXP_MB_IH=$mb timeout 60 ncu --kernel-name-base demangled --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-count 2 --section LaunchStats \
    $P benchmarks/scenes/bunny_field_10k.json -o /tmp/n.exr --width 64 --height 64 --spp 1 --backend cuda --quiet 2>&1 | grep -E "Registers Per" | sed "s/^/instanced mb $mb: /"
done
python3 $SW $P 3 benchmarks/scenes/bunny_field_10k.json "wide||--bvh wide" "wide-mb7|PT_EXP_MB_IH=7|--bvh wide" "wide-mb8|PT_EXP_MB_IH=8|--bvh wide" "binary||--bvh binary" "binary-mb8|PT_EXP_MB_IH=8|--bvh binary" 2>&1 | tail -7
python3 $SW $P 3 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json "pooled-bc||--tri-test box-clamped --prim-pool on" "pooled-bc-mb8|PT_EXP_MB_IH=8|--tri-test box-clamped --prim-pool on" "per-ray-bc||--tri-test box-clamped --prim-pool off" "per-ray-bc-mb8|PT_EXP_MB_IH=8|--tri-test box-clamped --prim-pool off" "binary-bc||--tri-test box-clamped --bvh binary" "binary-bc-mb8|PT_EXP_MB_IH=8|--tri-test box-clamped --bvh binary" 2>&1 | tail -14
