// The media kernels (src/integrator/media_pass_impl.h) on the CUDA backend, in a translation
// unit of their own: it compiles beside render_cuda.cu, and only scenes with media launch it.
#include "cuda/cuda_backend.cuh"
#include "src/integrator/media_pass_impl.h"

namespace pt {

template class MediaPass<CudaBackend>;

}  // namespace pt
