// Films whose memory the next leaf's save reuses. A leaf's film is merged into its sibling's
// and dropped; saving the next leaf into fresh memory faulted 124 MB of pages in for a 1080p
// film (~30 ms on the GPU machines' hosts, more than the download itself). Unbounded, yet it
// never raises the peak: a film is kept only where one was freed, and taken before a fresh one
// is made, so films kept plus films in use never exceed the most ever in use at once.
// Thread-safe: the render lanes take, the thread that merges gives.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "src/core/parallel_ranges.h"
#include "src/integrator/render_api.h"

namespace pt {

class FilmPool {
 public:
  FilmPool() = default;
  FilmPool(const FilmPool&) = delete;
  FilmPool& operator=(const FilmPool&) = delete;
  ~FilmPool() {
    stop_ = true;
    if (stocker_.joinable()) stocker_.join();
  }

  // Makes `count` films with `make`, a thread each, in the background, and keeps them, so
  // that the first saves find memory whose pages are in already (a first save into fresh
  // memory took 110-140 ms for a 1080p film on a GPU host, a later one ~11 ms).
  void Stock(size_t count, std::function<FilmState()> make) {
    if (stocker_.joinable()) stocker_.join();
    stocker_ = std::thread([this, count, make = std::move(make)] {
      ForRangesOnThreads(count, int(count), 1, [&](size_t lo, size_t hi) {
        for (size_t i = lo; i < hi && !stop_; ++i) Give(make());
      });
    });
  }

  // A film kept earlier, or an empty one.
  FilmState Take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (films_.empty()) return {};
    FilmState f = std::move(films_.back());
    films_.pop_back();
    return f;
  }

  // Keeps the film's memory for a later Take.
  void Give(FilmState&& film) {
    std::lock_guard<std::mutex> lock(mutex_);
    films_.push_back(std::move(film));
  }

 private:
  std::mutex mutex_;
  std::vector<FilmState> films_;
  std::atomic<bool> stop_{false};
  std::thread stocker_;
};

}  // namespace pt
