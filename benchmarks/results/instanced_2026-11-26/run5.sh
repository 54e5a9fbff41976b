# 51b2128 (instanced kernels without hit-test code when no material asks for it) against
# 4ad5173 (pathtracer_base): GPU tests, memcheck, the 10^4-bunny field at 64 spp (medians of 5),
# registers of the instanced traversal kernels.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; P=$B/pathtracer; H=$B/pathtracer_base; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
mkdir -p build/test_tmp && ln -sf $P build/pathtracer
export PT_SOURCE_DIR=$PWD PT_BINARY_DIR=$B PT_SHARED_DIR=$PWD/.device/shared
nvidia-smi --query-gpu=name --format=csv,noheader
echo "=== GPU tests"
$B/pt_tests --gtest_filter='*Gpu*:*Instanc*:*Wide*:*Bvh*:*Traversal*:Layouts*:GltfMaterialRender*:-*Mpi*' --gtest_brief=1 2>&1 | tail -5
echo "=== memcheck"
python3 benchmarks/scenes/make_bunny_field.py > /dev/null
for sc in scenes/instanced_shapes.json benchmarks/scenes/bunny_field_10k.json; do for bvh in wide binary; do
  compute-sanitizer --tool memcheck --error-exitcode 99 $P $sc -o /tmp/m.exr --width 64 --height 64 --spp 2 --backend cuda --bvh $bvh --quiet > /tmp/san.log 2>&1
  echo "$sc $bvh: exit $? $(grep 'ERROR SUMMARY' /tmp/san.log | tail -1)"; done; done
echo "=== registers"
for exe in pathtracer_base pathtracer; do for L in binary wide; do
  timeout 60 ncu --kernel-name-base demangled --kernel-name "regex:IntersectLayout|ShadowLayout" --launch-count 2 --section LaunchStats \
    $B/$exe benchmarks/scenes/bunny_field_10k.json -o /tmp/n.exr --width 64 --height 64 --spp 1 --backend cuda --bvh $L --quiet 2>&1 | grep -E "Registers Per|Local Memory|Layout<" | sed "s/(unsigned int.*//; s/^/$exe $L: /" | cut -c1-160
done; done
echo "=== field, 64 spp"
python3 $SW $P 5 benchmarks/scenes/bunny_field_10k.json "base-binary||--bvh binary --spp 64|$H" "base-wide||--bvh wide --spp 64|$H" "now-binary||--bvh binary --spp 64" "now-wide||--bvh wide --spp 64" 2>&1 | tail -6
