# nvidia-h100-x2 asked, 2x H200 given (141 GB each, 32 host cores). The tree of 28a81c2, packed
# with tools/pack_device.sh (bin/, mpi/, shared/ with the Stanford bunny only).
OUT=$OUT/mpi SCENES=bunny REPEATS=3 COUNTS="1 2" bash benchmarks/mpi_gpu_check.sh .device .
