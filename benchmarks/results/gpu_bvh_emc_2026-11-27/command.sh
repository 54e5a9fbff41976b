# H100 (nvidia-h100-x1), 16 host cores. NEW: ff42860 (the LBVH's extended Morton keys);
# BASE: bc3982d. Medians of 5 (10M: 3).
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=5 BIG_REPEATS=3 \
  WALL_VARIANTS="BASE NEW" STEPS="bvh" bash benchmarks/issue28_gpu_check.sh
