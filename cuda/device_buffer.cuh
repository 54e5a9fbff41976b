// Device memory with the Buffer interface WavefrontIntegrator expects. Plain cudaMalloc
// (never managed memory); peak usage is tracked for the statistics.
#pragma once

#include <atomic>
#include <utility>
#include <vector>

#include "cuda/cuda_check.cuh"
#include "cuda/staged_upload.cuh"

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

// The calling thread's stream for copies and fills on the current device. Never the legacy
// default stream: a synchronous cudaMemcpy there held another thread's kernels on its own
// non-blocking stream back for the whole copy (400 short kernels: 24.5 ms alone, 1,996 ms
// beside back-to-back film downloads, 26 ms beside the same downloads on a stream of their
// own; benchmarks/results/film_save_2026-11-25), and two render lanes share a GPU under MPI.
// Each copy is waited for before the call returns, so the backend's kernels, on their own
// stream, always see the data.
inline cudaStream_t ThreadCopyStream() {
  struct Streams {
    std::vector<std::pair<int, cudaStream_t>> byDevice;
    ~Streams() {
      for (auto& [device, stream] : byDevice) cudaStreamDestroy(stream);
    }
  };
  thread_local Streams streams;
  int device = 0;
  CudaCheck(cudaGetDevice(&device), "cudaGetDevice");
  for (auto& [d, stream] : streams.byDevice)
    if (d == device) return stream;
  cudaStream_t stream = nullptr;
  CudaCheck(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking), "cudaStreamCreate");
  streams.byDevice.emplace_back(device, stream);
  return stream;
}

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
    cudaStream_t copy = ThreadCopyStream();
    if (StagedUploadCopy(data_, src, bytes, copy)) return;
    CudaCheck(cudaMemcpyAsync(data_, src, bytes, cudaMemcpyHostToDevice, copy), "upload");
    CudaCheck(cudaStreamSynchronize(copy), "upload");
  }
  // Into dst's own memory when it has the size already (no fresh pages to fault in).
  void Download(std::vector<T>& dst) const {
    dst.resize(size_);
    if (!size_) return;
    cudaStream_t copy = ThreadCopyStream();
    CudaCheck(cudaMemcpyAsync(dst.data(), data_, Bytes(), cudaMemcpyDeviceToHost, copy),
              "download");
    CudaCheck(cudaStreamSynchronize(copy), "download");
  }
  void Zero() {
    if (!size_) return;
    cudaStream_t copy = ThreadCopyStream();
    CudaCheck(cudaMemsetAsync(data_, 0, Bytes(), copy), "cudaMemset");
    CudaCheck(cudaStreamSynchronize(copy), "cudaMemset");
  }
  T* Data() { return data_; }
  const T* Data() const { return data_; }
  size_t Size() const { return size_; }
  size_t Bytes() const { return size_ * sizeof(T); }

 private:
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
