// The CUDA backend: device arrays, one kernel launch per stage running the very same stage
// body as the CPU, Thrust for compaction, CUB and two kernels of ours for the ordering by
// material (render_cuda.cu).
// Included by exactly one translation unit (render_cuda.cu): Thrust compiles slowly.
#pragma once

#include <thrust/count.h>
#include <thrust/execution_policy.h>
#include <thrust/partition.h>

#include <algorithm>
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

// --ray-fetch dynamic (src/integrator/resumable_task.h): persistent warps, each lane carrying
// one item at a time. When at least kRefillLanes lanes of a warp are idle, they take the next
// items together (one atomic per warp), so a warp is not held by its longest item while most
// of its lanes wait. The loop's exit is warp-uniform: every lane idle and no items left.
constexpr uint32_t kRefillLanes = 8;

template <typename Task>
__global__ void DynamicFetchKernel(uint32_t n, uint32_t* next, Task task) {
  typename Task::State state;
  bool busy = false, exhausted = false;
  const uint32_t lane = threadIdx.x & 31u;
  for (;;) {
    const uint32_t idle = __ballot_sync(0xffffffffu, !busy);
    if (!exhausted && uint32_t(__popc(idle)) >= kRefillLanes) {
      const uint32_t leader = uint32_t(__ffs(idle)) - 1u, count = uint32_t(__popc(idle));
      uint32_t base = 0;
      if (lane == leader) base = atomicAdd(next, count);
      base = __shfl_sync(0xffffffffu, base, leader);
      exhausted = base + count >= n;
      if (!busy) {
        const uint32_t i = base + uint32_t(__popc(idle & ((1u << lane) - 1u)));
        if (i < n) busy = task.Start(state, i);
      }
    }
    if (__ballot_sync(0xffffffffu, busy) == 0) {
      if (exhausted) break;
      continue;
    }
    if (busy && task.Step(state)) {
      task.Finish(state);
      busy = false;
    }
  }
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

  template <typename F>
  void ParallelFor(Stage stage, uint32_t n, F body) {
    if (n == 0) return;
    constexpr uint32_t kBlock = 128;
    BeginStage(stage);
    ParallelForKernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, body);
    CudaCheck(cudaGetLastError(), "kernel launch");
    EndStage(stage);
  }

  // Task over [0, n) with dynamic fetch (the kernel above), on as many warps as fit at once.
  template <typename Task>
  void ParallelForDynamic(Stage stage, uint32_t n, const Task& task) {
    if (n == 0) return;
    constexpr uint32_t kBlock = 128;
    static const int blocksPerSm = [] {
      int blocks = 0;
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, DynamicFetchKernel<Task>, kBlock, 0);
      return blocks > 0 ? blocks : 1;
    }();
    const uint32_t grid = std::min(uint32_t(smCount_ * blocksPerSm), (n + kBlock - 1) / kBlock);
    BeginStage(stage);
    CudaCheck(cudaMemsetAsync(fetchNext_.Data(), 0, sizeof(uint32_t), stream_), "cudaMemsetAsync");
    DynamicFetchKernel<<<grid, kBlock, 0, stream_>>>(n, fetchNext_.Data(), task);
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
  StageTimes Times() const { return times_; }
  std::string Name() const { return "cuda"; }
  std::string DeviceName() const { return deviceName_; }
  int ThreadCount() const { return 0; }
  size_t PeakBytes() const { return DeviceMemoryTracker::peak.load(); }

 private:
  size_t defaultPaths_ = size_t(1) << 21;
  int smCount_ = 1;
  DeviceBuffer<uint32_t> fetchNext_;  // ParallelForDynamic's next item
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
