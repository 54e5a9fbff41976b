// The CUDA backend: device arrays, one kernel launch per stage running the very same stage
// body as the CPU, Thrust for compaction, CUB and two kernels of ours for the ordering by
// material (render_cuda.cu).
// Included by render_cuda.cu, which instantiates every Thrust call (Thrust compiles slowly),
// and by media_cuda.cu and denoise_cuda.cu, which make none.
#pragma once

#include <thrust/count.h>
#include <thrust/execution_policy.h>
#include <thrust/partition.h>

#include <string>
#include <vector>

#include "cuda/device_buffer.cuh"
#include "cuda/thrust_allocator.cuh"
#include "src/integrator/shade_order.h"
#include "src/integrator/stage_id.h"

namespace pt {

template <typename F>
__global__ void ParallelForKernel(uint32_t n, F body) {
  uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) body(i);
}

// The same for a stage that asks for kMinBlocks blocks of 128 threads resident per SM: the
// compiler fits its registers to that (a cap on this kernel only, not on the whole build).
template <int kMinBlocks, typename F>
__global__ void __launch_bounds__(128, kMinBlocks) ParallelForKernelBounded(uint32_t n, F body) {
  uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) body(i);
}

// A shade queue's kernel: its range [range[0], range[1]) was written on the device by an
// earlier kernel, so the host launches over the bounce's path count and never waits; threads
// past the range exit at once (as pbrt-v4's per-material work queues).
template <typename F>
__global__ void ParallelForRangeKernel(uint32_t n, const uint32_t* range, F body) {
  uint32_t begin = range[0], end = min(range[1], n);
  for (uint32_t i = begin + blockIdx.x * blockDim.x + threadIdx.x; i < end;
       i += gridDim.x * blockDim.x)
    body(i);
}

class CudaBackend {
 public:
  template <typename T>
  using Buffer = DeviceBuffer<T>;

  static constexpr bool kHostMemory = false;  // scene arrays are copied to the device
  static constexpr bool kLockstepLanes = true;  // warps diverge (--sort auto reads this)

  // Makes `device` the calling thread's current device: the thread that makes the backend
  // must be the one that renders with it.
  explicit CudaBackend(int device = 0);
  ~CudaBackend();

  // Paths in flight when --max-paths is not given: chosen from the device's free memory at
  // start-up (see the constructor). Larger waves keep the GPU full in the later bounces, where
  // few paths are left, and add each pixel's samples to the film in fewer passes.
  size_t DefaultPathsInFlight() const { return defaultPaths_; }

  // kMinBlocks > 0: the kernel keeps that many blocks per SM (its registers capped to fit).
  template <int kMinBlocks = 0, typename F>
  void ParallelFor(Stage stage, uint32_t n, F body) {
    if (n == 0) return;
    constexpr uint32_t kBlock = 128;
    BeginStage(stage);
    if constexpr (kMinBlocks > 0) {
      ParallelForKernelBounded<kMinBlocks>
          <<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, body);
    } else {
      ParallelForKernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, body);
    }
    CudaCheck(cudaGetLastError(), "kernel launch");
    EndStage(stage);
  }

  template <typename F>
  void ParallelForRange(Stage stage, uint32_t n, const uint32_t* range, F body) {
    if (n == 0) return;
    constexpr uint32_t kBlock = 128;
    BeginStage(stage);
    ParallelForRangeKernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, range, body);
    CudaCheck(cudaGetLastError(), "kernel launch");
    EndStage(stage);
  }

  template <typename Pred>
  uint32_t Partition(Stage stage, uint32_t* queue, uint32_t n, Pred keep) {
    if (n == 0) return 0;
    BeginStage(stage);
    uint32_t* end = thrust::partition(thrust::cuda::par(allocator_).on(stream_), queue, queue + n, keep);
    EndStage(stage);
    return uint32_t(end - queue);
  }

  template <typename Pred>
  uint32_t CountIf(Stage stage, const uint32_t* queue, uint32_t n, Pred pred) {
    if (n == 0) return 0;
    BeginStage(stage);
    auto count = thrust::count_if(thrust::cuda::par(allocator_).on(stream_), queue, queue + n, pred);
    EndStage(stage);
    return uint32_t(count);
  }

  // Orders (key, value) pairs by key (shade_order.h): counting sort (histogram, scan,
  // scatter) or CUB's radix sort over the key bits (or all 32). ReserveOrdering sizes the
  // scratch for shape.n pairs and returns its bytes.
  size_t ReserveOrdering(const OrderShape& shape);
  void OrderByKey(Stage stage, const OrderShape& shape, const OrderArrays& a);

  void Synchronize();
  // Makes this backend's device current on the calling thread (a thread that only copies).
  void BindThread();
  StageTimes Times() const { return times_; }
  void ResetTimes() { times_ = StageTimes{}; }
  // CUDA 12's default (CUDA_MODULE_LOADING unset or LAZY) loads a kernel at its first launch.
  bool LoadsKernelsOnFirstUse() const { return lazyLoading_; }
  std::string Name() const { return "cuda"; }
  std::string DeviceName() const { return deviceName_; }
  int ThreadCount() const { return 0; }
  size_t PeakBytes() const { return DeviceMemoryTracker::peak.load(); }

 private:
  size_t defaultPaths_ = size_t(1) << 21;
  int device_ = 0;
  bool lazyLoading_ = true;
  void BeginStage(Stage stage);
  void EndStage(Stage stage);

  cudaStream_t stream_ = nullptr;
  ThrustCachingAllocator allocator_;
  std::string deviceName_;
  StageTimes times_;
  // Event pairs recorded since the last Synchronize, folded into times_ there.
  struct Timing {
    Stage stage;
    cudaEvent_t start, end;
  };
  std::vector<Timing> pending_;
  std::vector<cudaEvent_t> eventPool_;
  DeviceBuffer<uint32_t> keyCounts_;  // counting sort: per key, then its cursor
  DeviceBuffer<uint8_t> orderScratch_;  // CUB's temporary storage
  cudaEvent_t TakeEvent();
};

}  // namespace pt
