// Statistics counters bumped from stage bodies. On the GPU a warp adds its total with one
// atomic (a single global counter hit by millions of threads would serialise); on the CPU a
// relaxed atomic add. Integer sums, so the totals do not depend on the order.
#pragma once

#include "src/core/pt.h"

namespace pt {

using Counter = unsigned long long;

PT_HDI void AddToCounter(Counter* counter, uint32_t value) {
#if PT_IS_GPU_CODE
  unsigned mask = __activemask();
  unsigned total = __reduce_add_sync(mask, value);
  int leader = __ffs(mask) - 1;
  if ((threadIdx.x & 31) == leader && total != 0) atomicAdd(counter, Counter(total));
#else
  if (value != 0) __atomic_fetch_add(counter, Counter(value), __ATOMIC_RELAXED);
#endif
}

}  // namespace pt
