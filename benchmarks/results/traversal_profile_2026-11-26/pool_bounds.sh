# Experimental build: the pooled kernels launched with __launch_bounds__(128, N) (PT_EXP_MB=N).
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
for mb in 7 8; do
  PT_EXP_MB=$mb timeout 60 ncu --kernel-name-base demangled --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-count 2 --section LaunchStats \
    $P benchmarks/scenes/bunny_cornell.json -o /tmp/n.exr --width 64 --height 64 --spp 1 --backend cuda --prim-pool on --quiet 2>&1 | grep -E "Registers Per" | sed "s/^/mb $mb: /"
  PT_EXP_MB=$mb $P benchmarks/scenes/breakfast_room.json -o /tmp/b$mb.exr --backend cuda --width 320 --height 180 --spp 16 --quiet --prim-pool on 2>/dev/null
done
$P benchmarks/scenes/breakfast_room.json -o /tmp/b0.exr --backend cuda --width 320 --height 180 --spp 16 --quiet --prim-pool off 2>/dev/null
.device/bin/image_compare /tmp/b0.exr /tmp/b7.exr | tail -1; .device/bin/image_compare /tmp/b0.exr /tmp/b8.exr | tail -1
S=benchmarks/scenes/breakfast_room.json,benchmarks/scenes/breakfast_room_bunnies.json,benchmarks/scenes/bunny_cornell.json
python3 $SW $P 3 $S "per-ray||--prim-pool off" "pooled||--prim-pool on" "pooled-mb7|PT_EXP_MB=7|--prim-pool on" "pooled-mb8|PT_EXP_MB=8|--prim-pool on" 2>&1 | tail -14
