// Every CUDA call is checked; failures become exceptions the app maps to exit status 3.
#pragma once

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

#include "src/integrator/render_api.h"

namespace pt {

struct CudaError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline void CudaCheck(cudaError_t err, const char* what) {
  if (err != cudaSuccess)
    throw CudaError(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(err));
}

// cudaMalloc of `bytes`; out of memory becomes OutOfDeviceMemory with the device's figures
// (held: what the renderer's buffers already take).
inline void CudaAllocate(void** ptr, size_t bytes, size_t held, const char* what) {
  cudaError_t err = cudaMalloc(ptr, bytes);
  if (err == cudaErrorMemoryAllocation) {
    cudaGetLastError();  // clear the sticky-free error so later calls work
    size_t freeBytes = 0, totalBytes = 0;
    cudaMemGetInfo(&freeBytes, &totalBytes);
    throw OutOfDeviceMemory(std::string("out of GPU memory in ") + what, bytes, held, freeBytes,
                            totalBytes);
  }
  CudaCheck(err, what);
}

}  // namespace pt
