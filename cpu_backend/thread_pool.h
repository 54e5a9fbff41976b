// A fixed set of worker threads that split [0, n) into chunks taken in any order. Results
// never depend on which thread ran a chunk: every work item writes only its own slots.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace pt {

class ThreadPool {
 public:
  explicit ThreadPool(int threads);  // 0 = all cores
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int Size() const { return int(workers_.size()) + 1; }  // the caller works too

  // Calls body(begin, end) over chunks of [0, n) and returns when all are done. chunk 0
  // picks a size; 1 hands out one item at a time (a few coarse tasks).
  template <typename F>
  void Run(uint32_t n, const F& body, uint32_t chunk = 0) {
    RunErased(n, [](const void* ctx, uint32_t b, uint32_t e) { (*static_cast<const F*>(ctx))(b, e); },
              &body, chunk);
  }

 private:
  using ChunkFn = void (*)(const void*, uint32_t, uint32_t);
  void RunErased(uint32_t n, ChunkFn fn, const void* ctx, uint32_t chunk);
  void WorkerLoop();
  void DrainChunks();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  uint64_t generation_ = 0;
  int busy_ = 0;
  bool quit_ = false;
  // The job in progress.
  ChunkFn fn_ = nullptr;
  const void* ctx_ = nullptr;
  uint32_t n_ = 0, chunk_ = 1;
  std::atomic<uint32_t> next_{0};
};

}  // namespace pt
