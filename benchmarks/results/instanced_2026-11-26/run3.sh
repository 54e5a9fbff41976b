# Final check of 0b54ad0 (both layouts' instanced walks in one loop): GPU tests, memcheck on
# instanced scenes, the 10^4-bunny field at 64 spp against e7b450a (pathtracer_head),
# alternating, medians of 5; then issue 10's matrix (gpu_bvh_check.sh, now with the field).
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; P=$B/pathtracer; H=$B/pathtracer_head; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
mkdir -p build/test_tmp && ln -sf $P build/pathtracer
export PT_SOURCE_DIR=$PWD PT_BINARY_DIR=$B PT_SHARED_DIR=$PWD/.device/shared
nvidia-smi --query-gpu=name --format=csv,noheader
echo "=== GPU tests"
$B/pt_tests --gtest_filter='*Gpu*:*Instanc*:*Wide*:*Bvh*:*Traversal*:-*Mpi*' --gtest_brief=1 2>&1 | tail -6
echo "=== memcheck"
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for sc in scenes/instanced_shapes.json benchmarks/scenes/bunny_field_10k.json; do for bvh in wide binary; do
  compute-sanitizer --tool memcheck --error-exitcode 99 $P $sc -o /tmp/m.exr --width 64 --height 64 --spp 2 --backend cuda --bvh $bvh --quiet > /tmp/san.log 2>&1
  echo "$sc $bvh: exit $? $(grep 'ERROR SUMMARY' /tmp/san.log | tail -1)"; done; done
echo "=== field, 64 spp"
python3 $SW $P 5 benchmarks/scenes/bunny_field_10k.json "head-binary||--bvh binary --spp 64|$H" "head-wide||--bvh wide --spp 64|$H" "now-binary||--bvh binary --spp 64" "now-wide||--bvh wide --spp 64" 2>&1 | tail -6
echo "=== matrix"
REPEATS=5 OUT=$OUT/matrix bash benchmarks/gpu_bvh_check.sh > /dev/null 2>&1; echo "exit $?"
tail -20 $OUT/matrix/bench.md
