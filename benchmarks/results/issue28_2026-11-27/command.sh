# Made on the device machines with binaries built here for sm_90 (BASE: bc3982d's pathtracer;
# NEW: main at the commit named in benchmarks/RESULTS.md), packed with their libraries.
# one_gpu_before_split/ (main d92408c + 9c62ea6, nvidia-h100-x1) and one_gpu/ (c398807):
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=3 \
  BIG_REPEATS=2 TEST_SECONDS=150 bash benchmarks/issue28_gpu_check.sh
#   (one_gpu/ with STEPS="tests regress cliff wall")
# two_gpus/ (c398807, nvidia-h100-x2, Debian's Open MPI 4.1.4 carried by tools/pack_mpi.sh):
OUT=$OUT/mpi REPEATS=3 SCENES="bunny breakfast" bash benchmarks/mpi_gpu_check.sh .device .
