// Every CUDA call is checked; failures become exceptions the app maps to exit status 3.
#pragma once

#include <cuda_runtime.h>

#include <stdexcept>
#include <string>

namespace pt {

struct CudaError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

inline void CudaCheck(cudaError_t err, const char* what) {
  if (err != cudaSuccess)
    throw CudaError(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(err));
}

}  // namespace pt
