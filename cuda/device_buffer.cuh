// Device memory with the Buffer interface WavefrontIntegrator expects. Plain cudaMalloc
// (never managed memory); peak usage is tracked for the statistics.
#pragma once

#include <atomic>
#include <utility>
#include <vector>

#include "cuda/cuda_check.cuh"

namespace pt {

struct DeviceMemoryTracker {
  static inline std::atomic<size_t> current{0}, peak{0};
  static void Add(size_t bytes) {
    size_t now = current += bytes;
    size_t p = peak.load();
    while (now > p && !peak.compare_exchange_weak(p, now)) {}
  }
  static void Remove(size_t bytes) { current -= bytes; }
};

template <typename T>
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  ~DeviceBuffer() { Free(); }

  void Resize(size_t n) {
    if (n == size_) return;
    Free();
    if (n == 0) return;
    CudaAllocate(reinterpret_cast<void**>(&data_), n * sizeof(T),
                 DeviceMemoryTracker::current.load(), "cudaMalloc");
    size_ = n;
    DeviceMemoryTracker::Add(Bytes());
  }
  void Upload(const std::vector<T>& src) { UploadBytes(src.data(), src.size() * sizeof(T)); }
  // Raw bytes into a buffer of ceil(bytes / sizeof(T)) elements (scene arrays of any type).
  void UploadBytes(const void* src, size_t bytes) {
    Resize((bytes + sizeof(T) - 1) / sizeof(T));
    if (!bytes) return;
    CudaCheck(cudaMemcpy(data_, src, bytes, cudaMemcpyHostToDevice), "upload");
    FinishLegacyStream();
  }
  void Download(std::vector<T>& dst) const {
    dst.resize(size_);
    if (size_) CudaCheck(cudaMemcpy(dst.data(), data_, Bytes(), cudaMemcpyDeviceToHost), "download");
  }
  void Zero() {
    if (!size_) return;
    CudaCheck(cudaMemset(data_, 0, Bytes()), "cudaMemset");
    FinishLegacyStream();
  }
  T* Data() { return data_; }
  const T* Data() const { return data_; }
  size_t Size() const { return size_; }
  size_t Bytes() const { return size_ * sizeof(T); }

 private:
  // A pageable upload and a memset may still be in flight on the legacy default stream when
  // they return, and the backend's kernels run on a non-blocking stream that does not wait
  // for it: finish them here, so that kernels always see the data (two render lanes share a
  // GPU under MPI, so a device-wide synchronise would stall the other lane).
  static void FinishLegacyStream() {
    CudaCheck(cudaStreamSynchronize(cudaStreamLegacy), "cudaStreamSynchronize");
  }
  void Free() {
    if (data_) {
      cudaFree(data_);
      DeviceMemoryTracker::Remove(Bytes());
    }
    data_ = nullptr;
    size_ = 0;
  }
  T* data_ = nullptr;
  size_t size_ = 0;
};

}  // namespace pt
