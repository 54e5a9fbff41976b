// Fresh memory for big host arrays, paged in on every core before it is written.
//
// A vector's resize over pages never touched takes one page fault per 4 KiB on the thread that
// resizes: for a 10M-triangle scene that is gigabytes faulted in one after another, most of the
// loading and preparation time (benchmarks/RESULTS.md, issue 28). ReserveOnThreads reserves the
// capacity and has the kernel make its pages present from several threads at once
// (madvise(MADV_POPULATE_WRITE), Linux 5.14+; elsewhere it only reserves), so the resize that
// follows writes to memory that is already there.
#pragma once

#include <cstddef>
#include <vector>

namespace pt {

// Makes the pages inside [begin, begin + bytes) present, split over up to `threads` threads (0:
// every core). Spans under a few MiB are left alone. Best effort: nothing happens where the
// kernel cannot.
void PrefaultOnThreads(void* begin, size_t bytes, int threads = 0);

// v.reserve(n), with the capacity beyond v's size paged in by PrefaultOnThreads.
template <typename T>
void ReserveOnThreads(std::vector<T>& v, size_t n, int threads = 0) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  PrefaultOnThreads(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(T), threads);
}

}  // namespace pt
