#!/usr/bin/env bash
# GPU checks of the glTF extension lobes (the layered shade variant), run on the GPU machine
# from the repository root after tools/pack_device.sh (the device tool carries .device/).
# Output goes to $OUT (or out/). What to look for:
#  1. gpu_ext_tests.log: GltfExtensionsGpu.* and GltfMaterialGpu.* pass (CPU/GPU agreement of
#     every extension scene), and the layered BSDF tests pass with the device build.
#  2. ext_<model>_{cpu,cuda}.png: the Khronos extension models (if carried under
#     .device/assets_extra) render on the GPU as on the CPU; timings in ext_times.txt.
#  3. sanitizer_layered.log: compute-sanitizer memcheck of a layered-variant render: 0 errors.
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"

echo "=== tests"
"$BIN/pt_tests" --gtest_filter='GltfExtensions*:GltfLayered*:GltfMaterialGpu*:Specialization*:SortModes*' \
  --gtest_brief=1 2>&1 | tee "$OUT/gpu_ext_tests.log" | tail -30

echo "=== models"
ASSETS="${ASSETS:-$ROOT/.device/assets_extra}"
SHARED_EXT="$ROOT/.device/shared/assets/khronos-ext"
: > "$OUT/ext_times.txt"
for model in "$SHARED_EXT/ClearCoatTest/glTF-Binary/ClearCoatTest.glb" \
             "$SHARED_EXT/SpecularTest/glTF-Binary/SpecularTest.glb" \
             "$SHARED_EXT/AnisotropyStrengthTest/glTF-Binary/AnisotropyStrengthTest.glb" \
             "$ASSETS"/*/glTF/*.gltf "$ASSETS"/*/glTF-Binary/*.glb; do
  [ -s "$model" ] || continue
  name=$(basename "${model%.*}")
  python3 benchmarks/gltf_extensions_cycles/model_scene.py "$model" "$OUT/$name.json" \
    --width 400 --height 400 --spp 256 --max-depth 8 > /dev/null || continue
  for backend in cuda cpu; do
    spp=256; [ "$backend" = cpu ] && spp=16
    "$BIN/pathtracer" "$OUT/$name.json" -o "$OUT/ext_${name}_$backend.png" --backend "$backend" \
      --spp "$spp" --stats-json "$OUT/ext_${name}_$backend.json" 2>&1 | grep -E "spp in|error" \
      | sed "s|^|$name $backend: |" >> "$OUT/ext_times.txt"
  done
done
cat "$OUT/ext_times.txt"

echo "=== compute-sanitizer memcheck, layered variant"
scene="$OUT/ClearCoatTest.json"
[ -s "$scene" ] && compute-sanitizer --tool memcheck --error-exitcode 99 "$BIN/pathtracer" "$scene" \
  -o "$OUT/san_layered.exr" --width 64 --height 64 --spp 4 --backend cuda --quiet \
  > "$OUT/sanitizer_layered.log" 2>&1; echo "memcheck exit $? ($(grep 'ERROR SUMMARY' "$OUT/sanitizer_layered.log" | tail -1))"
tar czf "$OUT/ext_images.tgz" -C "$OUT" $(cd "$OUT" && ls ext_*.png 2>/dev/null) 2>/dev/null || true
