// Entry point of the CUDA backend: the generic wavefront integrator over CudaBackend. Only
// launch plumbing lives here; the stage bodies are src/integrator/stages/.
#include "cuda/cuda_backend.cuh"
#include "src/integrator/backend_session.h"

namespace pt {

CudaBackend::CudaBackend(int device) {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0)
    throw BackendUnavailable("no CUDA device is available for --backend cuda");
  if (device < 0 || device >= count)
    throw BackendUnavailable("CUDA device " + std::to_string(device) + " does not exist (" +
                             std::to_string(count) + " found)");
  CudaCheck(cudaSetDevice(device), "cudaSetDevice");
  cudaDeviceProp prop;
  CudaCheck(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties");
  deviceName_ = prop.name;
  CudaCheck(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
}

CudaBackend::~CudaBackend() {
  cudaStreamSynchronize(stream_);
  for (auto& t : pending_) eventPool_.insert(eventPool_.end(), {t.start, t.end});
  for (cudaEvent_t e : eventPool_) cudaEventDestroy(e);
  cudaStreamDestroy(stream_);
}

cudaEvent_t CudaBackend::TakeEvent() {
  if (eventPool_.empty()) {
    cudaEvent_t e;
    CudaCheck(cudaEventCreate(&e), "cudaEventCreate");
    return e;
  }
  cudaEvent_t e = eventPool_.back();
  eventPool_.pop_back();
  return e;
}

void CudaBackend::BeginStage(Stage stage) {
  Timing t{stage, TakeEvent(), TakeEvent()};
  CudaCheck(cudaEventRecord(t.start, stream_), "cudaEventRecord");
  pending_.push_back(t);
}

void CudaBackend::EndStage(Stage) {
  CudaCheck(cudaEventRecord(pending_.back().end, stream_), "cudaEventRecord");
}

void CudaBackend::Synchronize() {
  CudaCheck(cudaStreamSynchronize(stream_), "cudaStreamSynchronize");
  for (Timing& t : pending_) {
    float ms = 0.0f;
    CudaCheck(cudaEventElapsedTime(&ms, t.start, t.end), "cudaEventElapsedTime");
    StageTime(times_, t.stage) += ms;
    eventPool_.push_back(t.start);
    eventPool_.push_back(t.end);
  }
  pending_.clear();
}

std::unique_ptr<RenderSession> MakeCudaSession(const Scene& scene, const RenderOptions& options,
                                               const RenderCallbacks& callbacks) {
  return std::make_unique<BackendSession<CudaBackend>>(scene, options, callbacks, options.device);
}

RenderResult RenderCuda(const Scene& scene, const RenderOptions& options,
                        const RenderCallbacks& callbacks) {
  return MakeCudaSession(scene, options, callbacks)->Render();
}

bool CudaBackendBuilt() { return true; }

int CudaDeviceCount() {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess) return 0;
  return count;
}

std::string CudaDeviceName() {
  cudaDeviceProp prop;
  if (CudaDeviceCount() == 0 || cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
  return prop.name;
}

}  // namespace pt
