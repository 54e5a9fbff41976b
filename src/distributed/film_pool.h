// Films whose memory the next leaf's save reuses. A leaf's film is merged into its sibling's
// and dropped; saving the next leaf into fresh memory faulted 124 MB of pages in for a 1080p
// film (~30 ms on the GPU machines' hosts, more than the download itself). Unbounded, yet it
// never raises the peak: a film is kept only where one was freed, and taken before a fresh one
// is made, so films kept plus films in use never exceed the most ever in use at once.
// Thread-safe: the render lanes take, the thread that merges gives.
#pragma once

#include <mutex>
#include <vector>

#include "src/integrator/render_api.h"

namespace pt {

class FilmPool {
 public:
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
};

}  // namespace pt
