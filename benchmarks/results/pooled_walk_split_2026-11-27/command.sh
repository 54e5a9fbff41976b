# H100 (nvidia-h100-x1), 16 host cores; two calls on one warm machine. NEW: this tree (the pooled
# GPU walk split in two: a warp team without a parallel-axis ray runs the copy without that
# code), BASE: bc3982d. Medians of 5.
# 1. Cornell box stages and whole runs (log.txt, stats.tar.gz, regs_*.txt):
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=5 BIG_REPEATS=3 \
  WALL_VARIANTS="BASE NEW" STEPS="regress wall" bash benchmarks/issue28_gpu_check.sh
# 2. The issue's render-rate scenes not in 1 (rates.tar.gz), interleaved BASE/NEW, 5 rounds:
for i in 1 2 3 4 5; do for b in base bin; do
  .device/$b/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet -o /tmp/p.png \
    --stats-json /tmp/pbrt_${b}_$i.json
  .device/$b/pathtracer benchmarks/scenes/breakfast_room_bunnies.json --spp 16 --bvh-build sah \
    --quiet -o /tmp/p.png --stats-json /tmp/b3_${b}_$i.json   # BASE: without --bvh-build (SAH)
done; done
# 3. pbrt-v4's box, where the regression stays (pbrt_probe.tar.gz), a later call on another
#    H100: BASE, NEW, NEW under CUDA_MODULE_LOADING=EAGER, and both with --bvh binary, 5 rounds:
for i in 1 2 3 4 5; do
  .device/base/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet -o /tmp/p.png --stats-json /tmp/q_base_$i.json
  .device/bin/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet -o /tmp/p.png --stats-json /tmp/q_new_$i.json
  CUDA_MODULE_LOADING=EAGER .device/bin/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet -o /tmp/p.png --stats-json /tmp/q_eager_$i.json
  .device/bin/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet --bvh binary -o /tmp/p.png --stats-json /tmp/q_newbin_$i.json
  .device/base/pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --quiet --bvh binary -o /tmp/p.png --stats-json /tmp/q_basebin_$i.json
done
