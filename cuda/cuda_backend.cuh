// The CUDA backend: device arrays, one kernel launch per stage running the very same stage
// body as the CPU, and Thrust for the queue operations (compaction, sort by material).
// Included by exactly one translation unit (render_cuda.cu): Thrust compiles slowly.
#pragma once

#include <thrust/count.h>
#include <thrust/execution_policy.h>
#include <thrust/partition.h>
#include <thrust/sort.h>

#include <string>
#include <vector>

#include "cuda/device_buffer.cuh"
#include "cuda/thrust_allocator.cuh"
#include "src/integrator/stage_id.h"

namespace pt {

template <typename F>
__global__ void ParallelForKernel(uint32_t n, F body) {
  uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) body(i);
}

class CudaBackend {
 public:
  template <typename T>
  using Buffer = DeviceBuffer<T>;

  static constexpr bool kHostMemory = false;  // scene arrays are copied to the device

  // Makes `device` the calling thread's current device: the thread that makes the backend
  // must be the one that renders with it.
  explicit CudaBackend(int device = 0);
  ~CudaBackend();

  // Enough paths to fill every SM several times over.
  size_t DefaultPathsInFlight() const { return size_t(1) << 21; }

  template <typename F>
  void ParallelFor(Stage stage, uint32_t n, F body) {
    if (n == 0) return;
    constexpr uint32_t kBlock = 128;
    BeginStage(stage);
    ParallelForKernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, body);
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

  void SortByKey(Stage stage, uint32_t* keys, uint32_t* queue, uint32_t n) {
    if (n == 0) return;
    BeginStage(stage);
    thrust::sort_by_key(thrust::cuda::par(allocator_).on(stream_), keys, keys + n, queue);
    EndStage(stage);
  }
  // Radix sort of (key, value) pairs double-buffers both.
  size_t SortScratchBytesPerPath(bool sorting) const { return sorting ? 8 : 0; }

  void Synchronize();
  StageTimes Times() const { return times_; }
  std::string Name() const { return "cuda"; }
  std::string DeviceName() const { return deviceName_; }
  int ThreadCount() const { return 0; }
  size_t PeakBytes() const { return DeviceMemoryTracker::peak.load(); }

 private:
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
  cudaEvent_t TakeEvent();
};

}  // namespace pt
