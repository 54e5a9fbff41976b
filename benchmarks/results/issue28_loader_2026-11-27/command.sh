# H100 (nvidia-h100-x1), 16 host cores. NEW: main 189b407 (the glTF loader's batches and the
# scene preparation on every core), BASE: bc3982d, both packed with their libraries.
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=3 \
  BIG_REPEATS=3 STEPS="wall bvh" bash benchmarks/issue28_gpu_check.sh
# CUDA module loading at start-up (the bunny Cornell box 1080p, 16 spp), three runs each:
for m in EAGER LAZY EAGER LAZY EAGER LAZY; do
  CUDA_MODULE_LOADING=$m .device/bin/pathtracer benchmarks/scenes/bunny_cornell.json --spp 16 \
    --quiet -o /tmp/x.png --stats-json s.json   # time_ms.background.device_start, total
done
