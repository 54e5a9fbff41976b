// Thrust asks for temporary storage on every sort or partition; cudaMalloc/cudaFree each time
// would cost more than the operation. This allocator keeps freed blocks for reuse.
#pragma once

#include <map>

#include "cuda/device_buffer.cuh"

namespace pt {

class ThrustCachingAllocator {
 public:
  using value_type = char;

  ThrustCachingAllocator() = default;
  ThrustCachingAllocator(const ThrustCachingAllocator&) = delete;
  ~ThrustCachingAllocator() {
    for (auto& [size, ptr] : free_) FreeBlock(ptr, size);
    for (auto& [ptr, size] : used_) FreeBlock(ptr, size);
  }

  char* allocate(std::ptrdiff_t bytes) {
    size_t n = size_t(bytes);
    auto it = free_.lower_bound(n);
    char* ptr;
    if (it != free_.end() && it->first < 2 * n + 4096) {
      n = it->first;
      ptr = it->second;
      free_.erase(it);
    } else {
      CudaAllocate(reinterpret_cast<void**>(&ptr), n, DeviceMemoryTracker::current.load(),
                   "cudaMalloc (thrust scratch)");
      DeviceMemoryTracker::Add(n);
    }
    used_[ptr] = n;
    return ptr;
  }

  void deallocate(char* ptr, size_t) {
    auto it = used_.find(ptr);
    free_.emplace(it->second, ptr);
    used_.erase(it);
  }

 private:
  static void FreeBlock(char* ptr, size_t size) {
    cudaFree(ptr);
    DeviceMemoryTracker::Remove(size);
  }
  std::multimap<size_t, char*> free_;
  std::map<char*, size_t> used_;
};

}  // namespace pt
