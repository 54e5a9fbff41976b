// Host-side bulk work on big arrays (film saves and merges, a big scene's primitives) split
// over a few threads: [0, n) in up to `threads` (at most the cores; 0 or less: every core)
// contiguous ranges of at least `minPerRange` items, body(lo, hi) on each, the first on the
// calling thread. Host only: device work goes through a backend.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace pt {

template <typename F>
void ForRangesOnThreads(size_t n, int threads, size_t minPerRange, const F& body) {
  int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  size_t parts = std::clamp<size_t>(n / std::max<size_t>(1, minPerRange), 1,
                                    size_t(threads > 0 ? std::min(threads, cores) : cores));
  std::vector<std::thread> workers;
  for (size_t p = 1; p < parts; ++p)
    workers.emplace_back([&, p] { body(n * p / parts, n * (p + 1) / parts); });
  body(0, n / parts);
  for (std::thread& t : workers) t.join();
}

}  // namespace pt
