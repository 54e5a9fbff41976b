# H100 (nvidia-h100-x1). TRIED AND NOT KEPT: the CLI tore the GPU's context down
# (cudaDeviceReset on a thread of its own, started when the output was; a part
# time_ms.device_release) instead of leaving it to the driver at exit. Every run then
# segfaulted at exit after writing its outputs (the main thread's copy streams, thread-local,
# destroyed after the reset), and the shell's wall time was no better (bunny 3.343 s; total
# 3,137.5 ms: the teardown took 57-80 ms on its thread, 24-52 ms of it after the output).
BASE=.device/bin NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=5 \
  WALL_VARIANTS="NEW" STEPS="wall" bash benchmarks/issue28_gpu_check.sh
