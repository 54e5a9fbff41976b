#include "src/core/prefault.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

#include "src/core/parallel_ranges.h"

namespace pt {

void PrefaultOnThreads(void* begin, size_t bytes, int threads) {
#ifdef MADV_POPULATE_WRITE
  constexpr size_t kMinBytes = size_t(4) << 20;        // below this one thread's faults are cheap
  constexpr size_t kMinPagesPerThread = size_t(1) << 10;  // 4 MiB of 4 KiB pages
  if (bytes < kMinBytes) return;
  const size_t page = size_t(sysconf(_SC_PAGESIZE));
  uintptr_t lo = (reinterpret_cast<uintptr_t>(begin) + page - 1) / page * page;
  uintptr_t hi = (reinterpret_cast<uintptr_t>(begin) + bytes) / page * page;
  if (hi <= lo) return;
  size_t pages = (hi - lo) / page;
  ForRangesOnThreads(pages, threads, kMinPagesPerThread, [&](size_t first, size_t last) {
    // A failure (an older kernel: EINVAL) only leaves the faults to the first write.
    madvise(reinterpret_cast<void*>(lo + first * page), (last - first) * page, MADV_POPULATE_WRITE);
  });
#else
  (void)begin, (void)bytes, (void)threads;
#endif
}

}  // namespace pt
