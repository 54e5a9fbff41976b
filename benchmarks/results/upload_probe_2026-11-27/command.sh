# H100 (nvidia-h100-x1), 16 host cores. One GiB of pageable, touched host memory to the device,
# three ways, 3 repetitions (a standalone probe, nvcc -O2 -arch=sm_90, not kept in the tree):
# - pageable: one cudaMemcpyAsync from the std::vector's memory on a non-blocking stream, synced;
# - staged: 3 pinned buffers of CHUNK (cudaHostAlloc: "alloc"), for each chunk THREADS host
#   threads memcpy their slice into the next free buffer (cudaEventSynchronize on the copy that
#   last used it), then cudaMemcpyAsync + cudaEventRecord; "copy" = first memcpy to the final
#   stream sync; "free" = cudaFreeHost of the buffers;
# - register: cudaHostRegister of the vector's memory, one copy, cudaHostUnregister.
# What cuda/staged_upload.cuh took from it: 3 x 16 MiB buffers, 8 threads (copy 48-56 ms per GiB
# against 155-163 pageable; 26-38 ms once to allocate the buffers).
./upload_probe   # output: upload_probe.txt
