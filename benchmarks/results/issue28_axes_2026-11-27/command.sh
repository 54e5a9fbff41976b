# H100, NEW: main 835ef01 (one parallel-axis cull: the scalar node test takes ParallelSlotKeep's
# mask, the frame step removed), BASE: bc3982d; medians of 3.
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=3 \
  STEPS="regress cliff" bash benchmarks/issue28_gpu_check.sh
