// The pinned buffers of cuda/staged_upload.cuh, made once per process (ahead, on a thread of
// their own, or by the first upload that pays for them) and used by one upload at a time.
#include "cuda/staged_upload.cuh"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "cuda/cuda_check.cuh"
#include "src/core/parallel_ranges.h"

namespace pt {
namespace {

constexpr size_t kChunk = size_t(16) << 20;
constexpr int kBuffers = 3;
constexpr int kMaxThreads = 8;  // host threads filling a buffer
constexpr size_t kMinFillPerThread = size_t(1) << 20;
// An upload this big makes the buffers itself when they are not there (26-38 ms once, against
// ~100 ms saved per GiB).
constexpr size_t kAllocateForBytes = size_t(256) << 20;

class StagingPool {
 public:
  static StagingPool& Get() {
    static StagingPool pool;
    return pool;
  }

  // Makes the buffers on a thread of its own (device: whose context to make them in).
  void PrepareAsync(int device) {
    std::lock_guard<std::mutex> lock(threadMutex_);
    if (preparer_.joinable()) return;
    preparer_ = std::thread([this, device] {
      cudaSetDevice(device);
      std::lock_guard<std::mutex> use(mutex_);
      Allocate();
    });
  }

  bool Copy(char* dst, const char* src, size_t bytes, cudaStream_t stream) {
    JoinPreparer();
    std::lock_guard<std::mutex> lock(mutex_);
    if (buffers_.empty() && (bytes < kAllocateForBytes || !Allocate())) return false;
    Run(dst, src, bytes, stream);
    return true;
  }

 private:
  StagingPool() = default;
  ~StagingPool() {
    JoinPreparer();
    for (char* b : buffers_) cudaFreeHost(b);  // at exit the context may be gone: not checked
  }

  void JoinPreparer() {
    std::lock_guard<std::mutex> lock(threadMutex_);
    if (preparer_.joinable()) preparer_.join();
  }

  // The buffers, or none (and false) when pinned memory is refused: uploads stay pageable.
  bool Allocate() {
    if (!buffers_.empty() || failed_) return !failed_;
    for (int k = 0; k < kBuffers; ++k) {
      char* b = nullptr;
      // Portable: lanes on other devices of the process use them too.
      if (cudaHostAlloc(&b, kChunk, cudaHostAllocPortable) != cudaSuccess) {
        cudaGetLastError();
        for (char* made : buffers_) cudaFreeHost(made);
        buffers_.clear();
        failed_ = true;
        return false;
      }
      buffers_.push_back(b);
    }
    return true;
  }

  void Run(char* dst, const char* src, size_t bytes, cudaStream_t stream) {
    cudaEvent_t done[kBuffers];  // per call: events belong to the current device
    for (cudaEvent_t& e : done)
      CudaCheck(cudaEventCreateWithFlags(&e, cudaEventDisableTiming), "cudaEventCreate");
    size_t chunks = (bytes + kChunk - 1) / kChunk;
    cudaError_t err = cudaSuccess;
    for (size_t c = 0; c < chunks && err == cudaSuccess; ++c) {
      int k = int(c % kBuffers);
      if (c >= size_t(kBuffers)) err = cudaEventSynchronize(done[k]);
      if (err != cudaSuccess) break;
      size_t at = c * kChunk, len = std::min(kChunk, bytes - at);
      char* to = buffers_[size_t(k)];
      ForRangesOnThreads(len, int(kMaxThreads), kMinFillPerThread, [&](size_t lo, size_t hi) {
        std::memcpy(to + lo, src + at + lo, hi - lo);
      });
      err = cudaMemcpyAsync(dst + at, buffers_[size_t(k)], len, cudaMemcpyHostToDevice, stream);
      if (err == cudaSuccess) err = cudaEventRecord(done[k], stream);
    }
    cudaError_t synced = cudaStreamSynchronize(stream);
    for (cudaEvent_t e : done) cudaEventDestroy(e);
    CudaCheck(err != cudaSuccess ? err : synced, "upload");
  }

  std::mutex mutex_;        // the buffers: one upload at a time
  std::mutex threadMutex_;  // the preparing thread
  std::thread preparer_;
  std::vector<char*> buffers_;
  bool failed_ = false;
};

}  // namespace

bool StagedUploadCopy(void* dst, const void* src, size_t bytes, cudaStream_t stream) {
  if (bytes < kStagedUploadMinBytes) return false;
  return StagingPool::Get().Copy(static_cast<char*>(dst), static_cast<const char*>(src), bytes,
                                 stream);
}

void CudaPrepareUploads(int localRank) {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) {
    cudaGetLastError();
    return;
  }
  StagingPool::Get().PrepareAsync(localRank % count);
}

}  // namespace pt
