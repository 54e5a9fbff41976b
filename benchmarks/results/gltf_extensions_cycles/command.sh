# Made on the CPU (2 cores, shared with a build) with main at c398807's build and Debian's
# blender 3.4.1, 2026-11-27; models from ../shared/assets/khronos-ext and /work/assets_extra
# (KhronosGroup glTF-Sample-Assets, see ../shared/assets/khronos-ext/SOURCE.md):
bash benchmarks/gltf_extensions_cycles/run.sh build benchmarks/results/gltf_extensions_cycles
# ratios.csv: per model, the whole object and a 3 x 3 grid of regions: object pixels, our mean
# luminance, Cycles', ours / Cycles. MODEL.png: ours (left) and Cycles (right), 200x200, 64 spp.
