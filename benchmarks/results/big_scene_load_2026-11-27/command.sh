# H100 (nvidia-h100-x1), 16 host cores. NEW: this tree (the indexed glTF load, arrays reserved
# for a file's later placements and paged in on every core, staged uploads through pinned buffers
# made beside the scene's preparation, the light table on every core, the LBVH's downloads into
# paged-in memory); BASE: bc3982d. Packed with tools/pack_device.sh (base beside it, see
# benchmarks/issue28_gpu_check.sh). Medians of 5 (the 10M scene: 3).
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=5 BIG_REPEATS=3 \
  WALL_VARIANTS="BASE NEW" STEPS="wall bvh" bash benchmarks/issue28_gpu_check.sh
