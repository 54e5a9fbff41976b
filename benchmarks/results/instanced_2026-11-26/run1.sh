# The one-loop two-level wide walk and one-instance top-level leaves against the commit before
# (.device/bin/pathtracer_head, e7b450a): GPU tests, memcheck, then the 10^4-bunny field and the
# flat scenes alternating both binaries. Run from the repository root on the GPU machine.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; P=$B/pathtracer; H=$B/pathtracer_head; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
mkdir -p build/test_tmp && ln -sf $P build/pathtracer
export PT_SOURCE_DIR=$PWD PT_BINARY_DIR=$B PT_SHARED_DIR=$PWD/.device/shared
nvidia-smi --query-gpu=name --format=csv,noheader
echo "=== GPU tests"
$B/pt_tests --gtest_filter='*Gpu*:*Instanc*:*Wide*:*Bvh*:*Traversal*:-*Mpi*' --gtest_brief=1 2>&1 | tail -8
echo "=== memcheck"
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for sc in scenes/instanced_shapes.json benchmarks/scenes/bunny_field_10k.json; do for bvh in wide binary; do
  compute-sanitizer --tool memcheck --error-exitcode 99 $P $sc -o /tmp/m.exr --width 64 --height 64 --spp 2 --backend cuda --bvh $bvh --quiet > /tmp/san.log 2>&1
  echo "$sc $bvh: exit $? $(grep 'ERROR SUMMARY' /tmp/san.log | tail -1)"; done; done
echo "=== field"
python3 $SW $P 3 benchmarks/scenes/bunny_field_10k.json "head-binary||--bvh binary|$H" "head-wide||--bvh wide|$H" "new-binary||--bvh binary" "new-wide||--bvh wide" 2>&1 | tail -6
python3 $SW $P 3 benchmarks/scenes/bunny_field_10k.json "head-binary-64||--bvh binary --spp 64|$H" "head-wide-64||--bvh wide --spp 64|$H" "new-binary-64||--bvh binary --spp 64" "new-wide-64||--bvh wide --spp 64" 2>&1 | tail -6
echo "=== flat"
python3 $SW $P 3 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json,../shared/peer-scenes/pbrt_cornell.json "head-wide||--bvh wide|$H" "new-wide||--bvh wide" 2>&1 | tail -8
