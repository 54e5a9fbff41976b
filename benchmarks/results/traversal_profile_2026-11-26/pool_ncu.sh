# ncu of the closest-hit kernel, per-ray vs pooled (PT_EXP_POOL), bounce 1 of small renders.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn $PWD/.device/shared ../shared; P=$PWD/.device/bin/pathtracer
for sc in breakfast_room bunny_cornell; do
  for m in 0 1; do
    PT_EXP_POOL=$m timeout 120 ncu --clock-control none --kernel-name-base demangled \
      --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-skip 2 --launch-count 2 \
      --section SpeedOfLight --section WarpStateStats --section LaunchStats --section Occupancy \
      --metrics smsp__inst_executed.sum,smsp__thread_inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio \
      $P benchmarks/scenes/$sc.json -o /tmp/n.exr --width 640 --height 360 --spp 4 --backend cuda \
      --bvh wide --quiet > "$OUT/ncu_${sc}_pool$m.txt" 2>&1
    echo "== $sc pool=$m"
    grep -E "^  [a-zA-Z].*Layout|Duration|inst_executed|Registers Per|Achieved Occupancy|Shared Memory Config|Block Limit Shared" "$OUT/ncu_${sc}_pool$m.txt" | sed 's/(unsigned int.*//; s/ParallelForKernel<void WavefrontIntegrator<CudaBackend>:://'
  done
done
