// Entry point of the CUDA backend: the generic wavefront integrator over CudaBackend. Only
// launch plumbing lives here; the stage bodies are src/integrator/stages/.
#include <cstdlib>

#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include "cuda/cuda_backend.cuh"
#include "src/integrator/backend_session.h"

namespace pt {

namespace {

constexpr uint32_t kOrderBlock = 256;
constexpr uint32_t kHistogramBlocks = 1024;

// Counting sort, pass 1: the count of every key, summed in shared memory per block first so
// that global atomics are one per key per block.
__global__ void KeyHistogramKernel(const uint32_t* keys, uint32_t n, uint32_t keyCount,
                                   uint32_t* counts) {
  extern __shared__ uint32_t local[];
  for (uint32_t k = threadIdx.x; k < keyCount; k += blockDim.x) local[k] = 0;
  __syncthreads();
  for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x)
    atomicAdd(&local[keys[i]], 1u);
  __syncthreads();
  for (uint32_t k = threadIdx.x; k < keyCount; k += blockDim.x)
    if (local[k]) atomicAdd(&counts[k], local[k]);
}

// Counting sort, pass 3 (after an exclusive scan turned counts into cursors): each thread's
// rank among its block's equal keys, each block's run of every key reserved with one global
// atomic, then the scatter. The order among equal keys varies between runs; shading reads
// only slots, so images do not.
__global__ void KeyScatterKernel(OrderArrays a, uint32_t n, uint32_t keyCount,
                                 uint32_t* cursor) {
  extern __shared__ uint32_t shared[];
  uint32_t* local = shared;
  uint32_t* base = shared + keyCount;
  for (uint32_t k = threadIdx.x; k < keyCount; k += blockDim.x) local[k] = 0;
  __syncthreads();
  uint32_t i = blockIdx.x * blockDim.x + threadIdx.x, key = 0, rank = 0;
  if (i < n) {
    key = a.keys[i];
    rank = atomicAdd(&local[key], 1u);
  }
  __syncthreads();
  for (uint32_t k = threadIdx.x; k < keyCount; k += blockDim.x)
    if (local[k]) base[k] = atomicAdd(&cursor[k], local[k]);
  __syncthreads();
  if (i < n) {
    uint32_t p = base[key] + rank;
    a.keysOut[p] = key;
    a.valuesOut[p] = a.values[i];
  }
}

int EndBit(const OrderShape& shape) {
  return shape.method == SortMethod::kRadixFullWidth ? 32 : int(shape.keyBits);
}

}  // namespace

// Grow-only: shading's material order and --ray-order share the scratch, each reserving its
// own shape.
size_t CudaBackend::ReserveOrdering(const OrderShape& shape) {
  size_t bytes = 0;
  if (shape.method == SortMethod::kCounting) {
    if (shape.keyCount > keyCounts_.Size()) keyCounts_.Resize(shape.keyCount);
    CudaCheck(cub::DeviceScan::ExclusiveSum(nullptr, bytes, keyCounts_.Data(), keyCounts_.Data(),
                                            int(shape.keyCount), stream_),
              "cub::DeviceScan::ExclusiveSum");
  } else {
    CudaCheck(cub::DeviceRadixSort::SortPairs(nullptr, bytes, static_cast<const uint32_t*>(nullptr),
                                              static_cast<uint32_t*>(nullptr),
                                              static_cast<const uint32_t*>(nullptr),
                                              static_cast<uint32_t*>(nullptr), int(shape.n), 0,
                                              EndBit(shape), stream_),
              "cub::DeviceRadixSort::SortPairs");
  }
  if (bytes > orderScratch_.Bytes() || orderScratch_.Bytes() == 0)
    orderScratch_.Resize(std::max<size_t>(bytes, 1));
  return orderScratch_.Bytes() + keyCounts_.Bytes();
}

void CudaBackend::OrderByKey(Stage stage, const OrderShape& shape, const OrderArrays& a) {
  if (shape.n == 0) return;
  BeginStage(stage);
  size_t bytes = orderScratch_.Bytes();
  if (shape.method == SortMethod::kCounting) {
    uint32_t* counts = keyCounts_.Data();
    size_t shared = shape.keyCount * sizeof(uint32_t);
    CudaCheck(cudaMemsetAsync(counts, 0, shared, stream_), "cudaMemsetAsync");
    uint32_t blocks = std::min(kHistogramBlocks, (shape.n + kOrderBlock - 1) / kOrderBlock);
    KeyHistogramKernel<<<blocks, kOrderBlock, shared, stream_>>>(a.keys, shape.n,
                                                                shape.keyCount, counts);
    CudaCheck(cub::DeviceScan::ExclusiveSum(orderScratch_.Data(), bytes, counts, counts,
                                            int(shape.keyCount), stream_),
              "cub::DeviceScan::ExclusiveSum");
    KeyScatterKernel<<<(shape.n + kOrderBlock - 1) / kOrderBlock, kOrderBlock, 2 * shared,
                       stream_>>>(a, shape.n, shape.keyCount, counts);
  } else {
    CudaCheck(cub::DeviceRadixSort::SortPairs(orderScratch_.Data(), bytes, a.keys, a.keysOut,
                                              a.values, a.valuesOut, int(shape.n), 0,
                                              EndBit(shape), stream_),
              "cub::DeviceRadixSort::SortPairs");
  }
  CudaCheck(cudaGetLastError(), "ordering kernels");
  EndStage(stage);
}

namespace {

// CUDA 12's default loads each kernel at its first launch; CUDA_MODULE_LOADING=EAGER loads
// every kernel of the binary when the context is made (0.1-0.2 s more start-up on an H100). The
// integrator's warm-up wave (WavefrontIntegrator::WarmUp) keeps lazy loading out of the
// render's time.
bool LazyModuleLoading() {
  const char* mode = std::getenv("CUDA_MODULE_LOADING");
  return mode == nullptr || std::string(mode) != "EAGER";
}

// The default number of paths in flight: the largest power of two up to 2^25 whose path state
// (counted twice over, for the queues, sort keys and scratch besides it) fits in a quarter of
// the free memory, so the scene and film keep the rest. Waves of 2^25 paths rendered the bunny
// Cornell 1.48x and the Breakfast Room 1.42x faster than waves of 2^21 on an H100 (RESULTS.md):
// fewer passes over the film, and the later bounces' few paths still fill the GPU. The image
// does not depend on the wave size.
size_t DefaultPathsFor(size_t freeBytes) {
  constexpr size_t kMin = size_t(1) << 18, kMax = size_t(1) << 25;
  size_t paths = kMax;
  while (paths > kMin && paths * 2 * kPathStateBytes > freeBytes / 4) paths /= 2;
  return paths;
}

}  // namespace

CudaBackend::CudaBackend(int device) : lazyLoading_(LazyModuleLoading()) {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0)
    throw BackendUnavailable("no CUDA device is available for --backend cuda");
  if (device < 0 || device >= count)
    throw BackendUnavailable("CUDA device " + std::to_string(device) + " does not exist (" +
                             std::to_string(count) + " found)");
  CudaCheck(cudaSetDevice(device), "cudaSetDevice");
  device_ = device;
  cudaDeviceProp prop;
  CudaCheck(cudaGetDeviceProperties(&prop, device), "cudaGetDeviceProperties");
  deviceName_ = prop.name;
  CudaCheck(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
  size_t freeBytes = 0, totalBytes = 0;
  CudaCheck(cudaMemGetInfo(&freeBytes, &totalBytes), "cudaMemGetInfo");
  defaultPaths_ = DefaultPathsFor(freeBytes);
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

void CudaBackend::BindThread() { CudaCheck(cudaSetDevice(device_), "cudaSetDevice"); }

void CudaBackend::Synchronize() {
  CudaCheck(cudaStreamSynchronize(stream_), "cudaStreamSynchronize");
  for (Timing& t : pending_) {
    float ms = 0.0f;
    CudaCheck(cudaEventElapsedTime(&ms, t.start, t.end), "cudaEventElapsedTime");
    AddStageTime(times_, t.stage, ms);
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

namespace {

// Nothing: its attributes, asked for on the start-up thread, make the driver load this file's
// module (67 MB of code on sm_90, 75-135 ms to load on an H100) beside the scene's loading
// instead of at the session's first launch. The kernels themselves still load one by one when
// first used (the warm-up wave), and the other files' modules (media, denoiser, GPU BVH
// builder) only for runs that use them.
__global__ void LoadRenderModuleKernel() {}

}  // namespace

int CudaStartDevice(int localRank) {
  const int count = CudaDeviceCount();
  if (count == 0) return 0;
  // Makes the device's primary context (and with eager loading loads every kernel); the
  // session's own cudaSetDevice later finds it ready.
  cudaFuncAttributes attributes;
  if (cudaSetDevice(localRank % count) != cudaSuccess || cudaFree(nullptr) != cudaSuccess ||
      cudaFuncGetAttributes(&attributes, LoadRenderModuleKernel) != cudaSuccess) {
    cudaGetLastError();  // the session reports the failure when it starts
  }
  return count;
}

std::string CudaDeviceName() {
  cudaDeviceProp prop;
  if (CudaDeviceCount() == 0 || cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return "";
  return prop.name;
}

}  // namespace pt
