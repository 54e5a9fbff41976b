#!/usr/bin/env bash
# The one command behind benchmarks/results/gltf_extensions_cycles/: each Khronos extension
# sample model rendered by us (CPU) and by Blender 3.4's Cycles (its own glTF importer) through
# the same front camera under a uniform white environment, then per-region ratios and
# side-by-side images. Models are read from ASSETS (default /work/assets_extra, see
# ../shared/assets/khronos-ext/SOURCE.md) and ../shared/assets/khronos-ext; missing ones are
# skipped.
#
#   bash benchmarks/gltf_extensions_cycles/run.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
build=${1:-$repo/build}
out=${2:-$repo/benchmarks/results/gltf_extensions_cycles}
assets=${ASSETS:-/work/assets_extra}
shared=${SHARED:-$repo/../shared/assets/khronos-ext}
size=${SIZE:-200}
spp=${SPP:-64}
depth=${DEPTH:-6}
mkdir -p "$out"
rm -f "$out/ratios.csv"
work=$(mktemp -d)
models=(
  "$shared/ClearCoatTest/glTF-Binary/ClearCoatTest.glb"
  "$shared/SpecularTest/glTF-Binary/SpecularTest.glb"
  "$assets/SheenChair/glTF/SheenChair.gltf"
  "$assets/SheenCloth/glTF/SheenCloth.gltf"
  "$assets/ToyCar/glTF/ToyCar.gltf"
  "$assets/ClearcoatWicker/glTF-Binary/ClearcoatWicker.glb"
  "$assets/UnlitTest/glTF-Binary/UnlitTest.glb"
  "$assets/MaterialsVariantsShoe/glTF/MaterialsVariantsShoe.gltf"
)
for model in "${models[@]}"; do
  [ -s "$model" ] || { echo "skipped (absent): $model"; continue; }
  name=$(basename "${model%.*}")
  /usr/bin/python3 "$here/model_scene.py" "$model" "$work/$name.json" --width "$size" \
    --height "$size" --spp "$spp" --max-depth "$depth" > /dev/null
  "$build/pathtracer" "$work/$name.json" -o "$work/$name.exr" \
    --backend cpu --quiet
  blender -b -P "$here/cycles_render.py" -- "$work/$name.json" "$work/${name}_cycles.exr" \
    "$spp" > "$work/$name.blender.log" 2>&1 || { tail -20 "$work/$name.blender.log"; exit 1; }
  blender -b -P "$here/compare.py" -- "$name" "$work/$name.exr" "$work/${name}_cycles.exr" \
    "$out" 2>&1 | grep -E "^$name," || true
done
rm -rf "$work"
