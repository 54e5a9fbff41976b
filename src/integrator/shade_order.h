// How paths are ordered for shading (--sort): the sort key of every material, and the
// methods that order a bounce's paths by key. Materials are ranked by shade queue, so each
// queue is one run of keys and `queues` finds a queue's paths by binary search in the
// ordered keys; escaped paths follow every material, and finished paths (queued only without
// compaction) come last, never shaded.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "src/integrator/render_api.h"
#include "src/integrator/shade_queues.h"

namespace pt {

// Counting sort keeps one counter per key in a GPU block's shared memory: above this many
// keys (materials + 2) the ordering is a radix sort instead, whatever was asked.
constexpr uint32_t kCountingSortMaxKeys = 4096;

struct ShadeKeys {
  std::vector<uint32_t> materialKey;  // per material, ranked by shade queue
  uint32_t escapedKey = 0;            // materials.size()
  uint32_t finishedKey = 0;           // escapedKey + 1
  uint32_t keyCount = 0;              // finishedKey + 1
  uint32_t keyBits = 1;               // ceil(log2(keyCount)), at least 1
  uint32_t queuesUsed = 0;            // bit q: some primitive's material is in queue q
  // Queue q's keys are [firstKey[q], firstKey[q + 1]); firstKey[kShadeQueueCount] = finished.
  std::array<uint32_t, kShadeQueueCount + 1> firstKey{};

  bool Uses(uint32_t q) const { return (queuesUsed >> q) & 1u; }
};

ShadeKeys MakeShadeKeys(const Scene& scene);

// The method a render uses: counting sort where the keys fit, else the radix sort.
SortMethod ResolveSortMethod(SortMethod asked, uint32_t keyCount);

// What --sort auto chooses for a scene, and why (the statistics print the reason). The rule
// is in shade_order.cpp and docs/sorting.md.
struct SortChoice {
  SortMode mode;
  std::string reason;
};
// lockstep: the backend runs neighbouring paths in lockstep (GPU warps), where divergence costs.
SortChoice ChooseSortMode(SortMode asked, const ShadeKeys& keys, FeatureClass featureClass,
                          bool lockstep = true);

// Shade queues holding surface hits (every queue but the escaped one) the scene uses.
uint32_t SurfaceQueuesUsed(const ShadeKeys& keys);
// Whether queue q holds costly materials: textured ones, plastic, glTF.
bool CostlyQueue(uint32_t q);

const char* SortModeName(SortMode mode);
const char* SortMethodName(SortMethod method);

// One ordering of n keys (keyCount distinct values, keyBits bits) by a method; the CUDA backend
// also sizes its scratch memory from it.
struct OrderShape {
  SortMethod method;
  uint32_t keyBits, keyCount, n;
};

// keys[i] and values[i] in; keysOut and valuesOut ordered by key (order among equal keys is
// the backend's: shading does not depend on it).
struct OrderArrays {
  const uint32_t* keys;
  const uint32_t* values;
  uint32_t* keysOut;
  uint32_t* valuesOut;
};

// Each queue's first key, captured by value by the kernel that finds the queues' ranges.
struct QueueKeyTable {
  uint32_t firstKey[kShadeQueueCount + 1];
};

// Entry q of the ranges: the first position of the ordered keys at or after queue q's first
// key (binary search; q == kShadeQueueCount gives the end of the shaded paths).
PT_HDI uint32_t QueueStart(const uint32_t* orderedKeys, uint32_t n, uint32_t firstKey) {
  uint32_t lo = 0, hi = n;
  while (lo < hi) {
    uint32_t mid = lo + (hi - lo) / 2;
    if (orderedKeys[mid] < firstKey) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

}  // namespace pt
