# ncu of the instanced closest-hit and shadow kernels (bounce 1 of a 640x360 4 spp render of the
# 10^4-bunny field), e7b450a (pathtracer_head: nested walks) against 4ad5173 (one loop).
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn $PWD/.device/shared ../shared; B=$PWD/.device/bin
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for exe in pathtracer_head pathtracer; do
  for L in binary wide; do
    timeout 150 ncu --clock-control none --kernel-name-base demangled \
      --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-skip 2 --launch-count 2 \
      --section SpeedOfLight --section WarpStateStats --section LaunchStats --section Occupancy \
      --metrics smsp__inst_executed.sum,smsp__thread_inst_executed.sum,smsp__thread_inst_executed_per_inst_executed.ratio \
      $B/$exe benchmarks/scenes/bunny_field_10k.json -o /tmp/n.exr --spp 4 --backend cuda \
      --bvh $L --quiet > "$OUT/ncu_${exe}_$L.txt" 2>&1
    echo "== $exe $L"
    grep -E "^  [a-zA-Z].*Layout|Duration|inst_executed|Registers Per|Achieved Occupancy|Local Memory" "$OUT/ncu_${exe}_$L.txt" | sed 's/(unsigned int.*//; s/ParallelForKernel<void WavefrontIntegrator<CudaBackend>:://'
  done
done
