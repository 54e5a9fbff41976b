// The CPU backend: host memory, and stage bodies run in loops on a thread pool. No rendering
// logic lives here; it only supplies what WavefrontIntegrator asks of a backend.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cpu_backend/thread_pool.h"
#include "src/integrator/shade_order.h"
#include "src/integrator/stage_id.h"

namespace pt {

// The bytes the CPU backend's buffers hold (path state, film, queues), now and at their peak:
// the renderer's own memory, the CPU's counterpart of the CUDA backend's device memory.
struct HostMemoryTracker {
  static inline std::atomic<size_t> current{0}, peak{0};
  static void Change(size_t before, size_t after) {
    if (after < before) {
      current -= before - after;
      return;
    }
    size_t now = current += after - before;
    size_t p = peak.load();
    while (now > p && !peak.compare_exchange_weak(p, now)) {}
  }
};

// std::allocator that default-initialises: a vector's resize(n) leaves new floats as they are.
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <typename U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
};

class CpuBackend {
 public:
  template <typename T>
  class Buffer {
   public:
    Buffer() = default;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer() { HostMemoryTracker::Change(Bytes(), 0); }

    void Resize(size_t n) { Tracked([&] { data_.resize(n, T{}); }); }
    // New elements left unset, for a buffer whose readers read only what was written (the
    // denoiser's planes: zeroing 420 MB took 0.2 s more at 1080p, one thread faulting it in).
    void ResizeForOverwrite(size_t n) { Tracked([&] { data_.resize(n); }); }
    void Upload(const std::vector<T>& src) {
      Tracked([&] { data_.assign(src.begin(), src.end()); });
    }
    void UploadBytes(const void* src, size_t bytes) {
      Tracked([&] { data_.resize((bytes + sizeof(T) - 1) / sizeof(T), T{}); });
      if (bytes) std::memcpy(data_.data(), src, bytes);
    }
    void Download(std::vector<T>& dst) const { dst.assign(data_.begin(), data_.end()); }
    void Zero() { std::fill(data_.begin(), data_.end(), T{}); }
    T* Data() { return data_.empty() ? nullptr : data_.data(); }
    const T* Data() const { return data_.empty() ? nullptr : data_.data(); }
    size_t Size() const { return data_.size(); }
    size_t Bytes() const { return data_.size() * sizeof(T); }

   private:
    template <typename F>
    void Tracked(F change) {
      size_t before = Bytes();
      change();
      HostMemoryTracker::Change(before, Bytes());
    }
    std::vector<T, DefaultInitAllocator<T>> data_;
  };

  // The stages run on the host: scene arrays are read in place, never copied.
  static constexpr bool kHostMemory = true;
  // Each thread runs its paths one by one: no warp divergence (--sort auto reads this).
  static constexpr bool kLockstepLanes = false;

  explicit CpuBackend(int threads) : pool_(threads) {}

  // Paths in flight: enough to keep every core busy, few enough that path state stays
  // near the caches.
  size_t DefaultPathsInFlight() const { return size_t(1) << 16; }

  template <int kMinBlocks = 0, typename F>
  void ParallelFor(Stage stage, uint32_t n, const F& body) {  // (kMinBlocks: a GPU matter)
    auto t0 = Clock::now();
    pool_.Run(n, [&body](uint32_t begin, uint32_t end) {
      // A copy of the body whose captures no store can reach, and items that are independent
      // (threads run them in any order): GCC may then vectorise a body of plain arithmetic
      // over arrays (src/denoise/) without proving it alias-free.
      F local = body;
#pragma GCC ivdep
      for (uint32_t i = begin; i < end; ++i) local(i);
    });
    AddTime(stage, t0);
  }

  // body(t) for t in [0, n), each a task of its own that a free thread takes: coarse work
  // that balances itself (the denoiser's tiles, taken from a counter by ThreadCount() tasks).
  template <typename F>
  void ParallelTasks(Stage stage, uint32_t n, const F& body) {
    auto t0 = Clock::now();
    pool_.Run(n, [&body](uint32_t begin, uint32_t end) {
      for (uint32_t t = begin; t < end; ++t) body(t);
    }, 1);
    AddTime(stage, t0);
  }

  // body(i) for i in [range[0], range[1]): a shade queue's kernel, its range found by an
  // earlier stage (read here on the host; the CUDA backend reads it on the device).
  template <typename F>
  void ParallelForRange(Stage stage, uint32_t n, const uint32_t* range, const F& body) {
    uint32_t begin = range[0], end = std::min(range[1], n);
    if (begin >= end) return;
    ParallelFor(stage, end - begin, [&body, begin](uint32_t i) { body(begin + i); });
  }

  // Keeps the queue entries for which keep(id) holds, in order; returns how many.
  template <typename Pred>
  uint32_t Partition(Stage stage, uint32_t* queue, uint32_t n, const Pred& keep) {
    auto t0 = Clock::now();
    uint32_t* end = std::stable_partition(queue, queue + n, keep);
    AddTime(stage, t0);
    return uint32_t(end - queue);
  }

  template <typename Pred>
  uint32_t CountIf(Stage stage, const uint32_t* queue, uint32_t n, const Pred& pred) {
    auto t0 = Clock::now();
    uint32_t count = uint32_t(std::count_if(queue, queue + n, pred));
    AddTime(stage, t0);
    return count;
  }

  // Orders (key, value) pairs by key (shade_order.h): a stable counting sort, or std::sort of
  // packed pairs for both radix methods (the host has no radix sort worth its name). Returns
  // the scratch bytes an ordering of shape.n pairs holds.
  size_t ReserveOrdering(const OrderShape& shape);
  void OrderByKey(Stage stage, const OrderShape& shape, const OrderArrays& a);

  void Synchronize() {}
  void BindThread() {}  // host memory: any thread may copy
  StageTimes Times() const { return times_; }
  void ResetTimes() { times_ = StageTimes{}; }
  bool LoadsKernelsOnFirstUse() const { return false; }  // compiled into the binary
  std::string Name() const { return "cpu"; }
  std::string DeviceName() const;
  int ThreadCount() const { return pool_.Size(); }
  size_t PeakBytes() const { return HostMemoryTracker::peak.load(); }

 private:
  using Clock = std::chrono::steady_clock;
  void AddTime(Stage stage, Clock::time_point t0) {
    AddStageTime(times_, stage,
                 std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }

  ThreadPool pool_;
  StageTimes times_;
  std::vector<uint64_t> sortScratch_;
  std::vector<uint32_t> keyCursor_;
};

}  // namespace pt
