# The review's refactors (the pooled walk on WideWalk's steps, ForTraversal, InstanceLevel)
# against 88a4ef7 (pathtracer_base): GPU tests, memcheck, then renders alternating, medians of 3.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; P=$B/pathtracer; H=$B/pathtracer_base; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
mkdir -p build/test_tmp && ln -sf $P build/pathtracer
export PT_SOURCE_DIR=$PWD PT_BINARY_DIR=$B PT_SHARED_DIR=$PWD/.device/shared
nvidia-smi --query-gpu=name --format=csv,noheader
$B/pt_tests --gtest_filter='*Gpu*:*Instanc*:*Wide*:*Bvh*:*Traversal*:Layouts*:GltfMaterialRender*:PrimPool*:-*Mpi*' --gtest_brief=1 2>&1 | tail -4
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for args in "benchmarks/scenes/breakfast_room.json --prim-pool on" "benchmarks/scenes/breakfast_room.json --prim-pool on --tri-test box-clamped" "benchmarks/scenes/bunny_field_10k.json --bvh wide"; do
  compute-sanitizer --tool memcheck --error-exitcode 99 $P $args -o /tmp/m.exr --width 64 --height 64 --spp 2 --backend cuda --quiet > /tmp/san.log 2>&1
  echo "memcheck $args: exit $? $(grep 'ERROR SUMMARY' /tmp/san.log | tail -1)"; done
python3 $SW $P 3 benchmarks/scenes/breakfast_room.json "base||--prim-pool on|$H" "now||--prim-pool on" "base-bc||--prim-pool on --tri-test box-clamped|$H" "now-bc||--prim-pool on --tri-test box-clamped" "base-perray||--prim-pool off|$H" "now-perray||--prim-pool off" 2>&1 | tail -8
python3 $SW $P 3 benchmarks/scenes/bunny_field_10k.json "base-wide||--bvh wide --spp 64|$H" "now-wide||--bvh wide --spp 64" "base-binary||--bvh binary --spp 64|$H" "now-binary||--bvh binary --spp 64" 2>&1 | tail -6
