# Check of 4ad5173 (the binary walks share their interior step): GPU tests, memcheck, the
# 10^4-bunny field (64 spp) and the flat scenes against e7b450a (pathtracer_head), medians of 5.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; P=$B/pathtracer; H=$B/pathtracer_head; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
mkdir -p build/test_tmp && ln -sf $P build/pathtracer
export PT_SOURCE_DIR=$PWD PT_BINARY_DIR=$B PT_SHARED_DIR=$PWD/.device/shared
nvidia-smi --query-gpu=name --format=csv,noheader
echo "=== GPU tests"
$B/pt_tests --gtest_filter='*Gpu*:*Instanc*:*Wide*:*Bvh*:*Traversal*:Layouts*:-*Mpi*' --gtest_brief=1 2>&1 | tail -5
echo "=== memcheck"
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for sc in scenes/instanced_shapes.json benchmarks/scenes/bunny_field_10k.json benchmarks/scenes/bunny_cornell.json; do for bvh in wide binary; do
  compute-sanitizer --tool memcheck --error-exitcode 99 $P $sc -o /tmp/m.exr --width 64 --height 64 --spp 2 --backend cuda --bvh $bvh --quiet > /tmp/san.log 2>&1
  echo "$sc $bvh: exit $? $(grep 'ERROR SUMMARY' /tmp/san.log | tail -1)"; done; done
echo "=== field, 64 spp"
python3 $SW $P 5 benchmarks/scenes/bunny_field_10k.json "head-binary||--bvh binary --spp 64|$H" "head-wide||--bvh wide --spp 64|$H" "now-binary||--bvh binary --spp 64" "now-wide||--bvh wide --spp 64" 2>&1 | tail -6
echo "=== flat, binary layout"
python3 $SW $P 3 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json "head-binary||--bvh binary|$H" "now-binary||--bvh binary" 2>&1 | tail -6
