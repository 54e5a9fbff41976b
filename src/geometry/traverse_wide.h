// Wide (8-ary, compressed) BVH traversal after Ylitie, Karras and Laine (2017): a node is read
// with five 16-byte loads, its eight quantised child boxes are tested at once, and the hit
// children are kept as a bit mask (a "group") instead of one stack entry each. Interior hits
// are visited in the order the build chose for the ray's octant (on the GPU's closest-hit walks
// the nearest one first: kWideNearestFirst); the primitives of hit leaves go to the leaf
// callback (same contract as traverse_binary.h) one at a time.
//
// The box test is conservative although it works on quantised boxes with the cheap form
// t = q * (scale / d) + (origin - o) / d: see kWideSlack in wide_node_test.h.
#pragma once

#include "src/geometry/traverse_binary.h"
#include "src/geometry/wide_node_test.h"

namespace pt {

// One stack entry per level of the wide tree (bvh_wide.h checks the tree fits).
constexpr int kWideStackSize = kBvhMaxDepth + 32;

struct WideBvh {
  const WideBvhNode* nodes = nullptr;
  uint32_t nodeCount = 0;
};

PT_HDI WideBvh SceneWideBvh(const SceneView& s) { return WideBvh{s.wideNodes, s.nodeCount}; }

namespace detail {

PT_HDI uint32_t HighestBit(uint32_t x) {  // x != 0
#if PT_IS_GPU_CODE
  return 31u - uint32_t(__clz(x));
#else
  return 31u - uint32_t(__builtin_clz(x));
#endif
}
PT_HDI uint32_t LowestBit(uint32_t x) {  // x != 0
#if PT_IS_GPU_CODE
  return uint32_t(__ffs(x)) - 1u;
#else
  return uint32_t(__builtin_ctz(x));
#endif
}
PT_HDI uint32_t PopCount8(uint32_t x) {  // x < 256
#if PT_IS_GPU_CODE
  return uint32_t(__popc(x));
#elif defined(__POPCNT__)
  return uint32_t(__builtin_popcount(x));
#else
  // Baseline x86-64 has no popcnt instruction (the builtin becomes a libgcc call).
  x = x - ((x >> 1) & 0x55u);
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return (x + (x >> 4)) & 0x0fu;
#endif
}


}  // namespace detail

// On the GPU, a node's hit primitives are tested at once only when enough lanes of the warp have
// some (Ylitie et al. 2017's postponing): otherwise they wait on the stack as a primitive group
// while the warp keeps traversing together. At most kWidePostponed such groups at a time, on
// top of the one entry per level of the tree.
constexpr int kWidePostponed = 16;
constexpr int kWideStackCapacity = kWideStackSize + kWidePostponed;

// Whether a walk takes each node's nearest hit interior child first (the rest of the group in
// the octant order): on the GPU for closest hits, where it cut the bunny's closest-hit stage by
// 11% (a hit found sooner culls more); not for occlusion (no gain), nor on the CPU, where the
// next node then waits on the minimum and walks were 7-12% slower (benchmarks/RESULTS.md).
template <TraceMode kMode>
constexpr bool kWideNearestFirst = PT_IS_GPU_CODE && kMode == TraceMode::kClosest;

namespace detail {

// Whether this lane's primitives should wait: fewer than a fifth of the active lanes have any.
PT_HDI bool PostponePrims(bool hasPrims) {
#if PT_IS_GPU_CODE
  const uint32_t active = __activemask();
  const uint32_t withPrims = __ballot_sync(active, hasPrims);
  return hasPrims && 5 * __popc(withPrims) < __popc(active);
#else
  return false;  // one ray at a time: nothing to wait for
#endif
}

// The ray's constants for the node test.
PT_HDI_HOT WideRay MakeWideRay(const Ray& ray) {
  WideRay r;
  r.o = ray.o;
  r.invDir = vec3(1.0f / ray.d.x, 1.0f / ray.d.y, 1.0f / ray.d.z);
  r.neg[0] = r.invDir.x < 0.0f;  // 1/d is never -0; 1/-0 = -inf counts as negative
  r.neg[1] = r.invDir.y < 0.0f;
  r.neg[2] = r.invDir.z < 0.0f;
  r.octInv = 7u - (uint32_t(r.neg[0]) | uint32_t(r.neg[1]) << 1 | uint32_t(r.neg[2]) << 2);
  // Parallel axes (wide_node_test.h): |d_a| at most 2^-64 of the largest component, or 1 / d_a
  // infinite.
#ifdef PT_WIDE_AVX2
  r.oV = _mm_setr_ps(r.o.x, r.o.y, r.o.z, 0.0f);
  r.invDirV = _mm_setr_ps(r.invDir.x, r.invDir.y, r.invDir.z, 0.0f);
  const __m128 sign = _mm_set1_ps(-0.0f);
  const __m128 absD = _mm_andnot_ps(sign, _mm_setr_ps(ray.d.x, ray.d.y, ray.d.z, 0.0f));
  const __m128 largest = _mm_max_ps(_mm_max_ps(absD, _mm_shuffle_ps(absD, absD, 0xc9)),
                                    _mm_shuffle_ps(absD, absD, 0xd2));  // in lanes 0-2
  const __m128 parallel = _mm_or_ps(
      _mm_cmpngt_ps(absD, _mm_mul_ps(largest, _mm_set1_ps(0x1p-64f))),
      _mm_cmpeq_ps(_mm_andnot_ps(sign, r.invDirV), _mm_set1_ps(kInfinity)));
  r.parallel = uint32_t(_mm_movemask_ps(parallel)) & 7u;
#else
  const float ax = fabsf(ray.d.x), ay = fabsf(ray.d.y), az = fabsf(ray.d.z);
  const float small = 0x1p-64f * fmaxf(ax, fmaxf(ay, az));
  r.parallel = (uint32_t(!(ax > small)) | uint32_t(fabsf(r.invDir.x) == kInfinity)) |
               (uint32_t(!(ay > small)) | uint32_t(fabsf(r.invDir.y) == kInfinity)) << 1 |
               (uint32_t(!(az > small)) | uint32_t(fabsf(r.invDir.z) == kInfinity)) << 2;
#endif
  for (int a = 0; a < 3; ++a) {
    r.nearWord[a] = (r.neg[a] ? 14u : 8u) + 2u * uint32_t(a);
    r.farWord[a] = (r.neg[a] ? 8u : 14u) + 2u * uint32_t(a);
  }
  return r;
}

// A group's next interior child: takes `first` if set, else the group's highest bit; returns the
// child's node index.
PT_HDI_HOT uint32_t NextChild(uint32_t groupBase, uint32_t* groupMask, uint32_t octInv,
                              uint32_t first = 0) {
  const uint32_t bit = first != 0 ? first : HighestBit(*groupMask);
  *groupMask &= ~(1u << bit);
  const uint32_t slot = (bit - 24u) ^ octInv;
  return groupBase + PopCount8(*groupMask & 0xffu & ((1u << slot) - 1u));
}

// The groups waiting in a wide walk. Kept apart from WideWalk's scalars: an array indexed at
// run time lives in local memory on the GPU, and in one struct it took the scalars there too.
template <int kCapacity>
struct WideStack {
  uint32_t base[kCapacity], mask[kCapacity];
};

// A wide walk's state: the current node group (interior hits of a node: base = first interior
// child, mask = interior hit bits 24-31 | interior mask 0-7), the current primitive group, and
// the groups waiting on the stack. A stack entry whose mask has no bit above 23 is a postponed
// primitive group (base, primitive bits). A step at a time, so that one loop can also walk two
// levels (traverse_instanced.h).
template <int kCapacity>
struct WideWalk {
  WideStack<kCapacity>& stack;
  int stackSize = 0, postponed = 0;
  // The root is the one child of a virtual group (base 0, empty interior mask: index 0).
  uint32_t groupBase = 0, groupMask = 0x80000000u;
  uint32_t primBase = 0, primMask = 0;
  uint32_t first = 0;  // the current group's child to take first (0: the octant order's)

  PT_HDI_HOT explicit WideWalk(WideStack<kCapacity>& s) : stack(s) {}
  PT_HDI_HOT bool HasNode() const { return groupMask > 0x00ffffffu; }
  PT_HDI_HOT void Restart() {  // at the root of another tree
    groupBase = 0;
    groupMask = 0x80000000u;
    first = 0;
  }
  PT_HDI_HOT void Push(uint32_t base, uint32_t mask) {
    stack.base[stackSize] = base;
    stack.mask[stackSize] = mask;
    ++stackSize;
  }
  // Takes the group's next interior child (the rest of the group waits on the stack) and tests
  // it: its interior hits become the group, its primitive hits the primitive group, unless
  // kPostpone and too few lanes have primitives (PostponePrims).
  // kNearest: the new group's nearest child is taken first (closest-hit walks).
  template <bool kPostpone = true, bool kNearest = false, bool kParallel = true>
  PT_HDI_HOT void VisitNext(const WideBvhNode* nodes, const WideRay& r, float tMax) {
    const uint32_t index = NextChild(groupBase, &groupMask, r.octInv, first);
    if (HasNode() && stackSize < kCapacity) Push(groupBase, groupMask);
    const WideNodeHits n = TestWideNode<kNearest, kParallel>(nodes + index, r, tMax);
    first = n.nearest;
    groupBase = n.childBase;
    groupMask = (n.hits & 0xff000000u) | n.innerMask;
    primBase = n.primBase;
    primMask = n.hits & 0x00ffffffu;
    if (kPostpone && PostponePrims(primMask != 0) && HasNode() && postponed < kWidePostponed &&
        stackSize < kCapacity) {
      Push(primBase, primMask);
      ++postponed;
      primMask = 0;
    }
  }
  // Hands the primitive group's primitives to stop(index), lowest bit first, until it returns
  // true (an occlusion walk's blocker): then true, with the rest of the group dropped.
  template <typename StopFn>
  PT_HDI_HOT bool TestPrims(StopFn&& stop) {
    while (primMask != 0) {
      const uint32_t bit = LowestBit(primMask);
      primMask &= primMask - 1u;
      if (stop(primBase + bit)) return true;
    }
    return false;
  }
  // The next waiting group, once the current one has no interior child left; false when none.
  PT_HDI_HOT bool Pop() {
    if (stackSize == 0) return false;
    --stackSize;
    first = 0;
    if (stack.mask[stackSize] > 0x00ffffffu) {
      groupBase = stack.base[stackSize];
      groupMask = stack.mask[stackSize];
    } else {  // a postponed primitive group
      primBase = stack.base[stackSize];
      primMask = stack.mask[stackSize];
      groupMask = 0;
      --postponed;
    }
    return true;
  }
};

}  // namespace detail

namespace detail {

// The walk of Traverse, for a ray made by MakeWideRay. kParallel: the node test checks the
// ray's parallel axes (false only for a ray without any).
template <TraceMode kMode, bool kNearest, bool kParallel, typename LeafFn>
PT_HDI void WalkWide(const WideBvh& bvh, const WideRay& r, float* tMaxInOut, LeafFn& leaf,
                     TraversalCounters* counters) {
  float tMax = *tMaxInOut;
  uint32_t nodesVisited = 0;
  WideStack<kWideStackCapacity> stack;
  WideWalk<kWideStackCapacity> w(stack);
  for (;;) {
    if (w.primMask == 0 && w.HasNode()) {
      ++nodesVisited;
      w.template VisitNext<true, kNearest, kParallel>(bvh.nodes, r, tMax);
    }
    const bool done = w.TestPrims([&](uint32_t prim) {
      return leaf(prim, 1u, &tMax) && kMode == TraceMode::kAny;
    });
    if (done || (!w.HasNode() && !w.Pop())) break;
  }
  *tMaxInOut = tMax;
  if (counters) counters->nodes += nodesVisited;
}

}  // namespace detail

// Walks a wide BVH: the current node group is consumed highest bit first (after the nearest
// child when kNearest); the rest of a group waits on the stack. Hit primitives go to the leaf
// callback; *tMax as in the binary traversal.
template <TraceMode kMode, typename LeafFn, bool kNearest = kWideNearestFirst<kMode>>
PT_HDI void Traverse(const WideBvh& bvh, const Ray& ray, float* tMaxInOut, LeafFn& leaf,
                     TraversalCounters* counters) {
  if (bvh.nodeCount == 0 || !TraceableRay(ray)) return;
  const detail::WideRay r = detail::MakeWideRay(ray);
#if PT_IS_GPU_CODE
  // Two copies of the walk on the GPU: rays without a parallel axis (nearly all, in most
  // scenes) run one with no parallel-axis code in its loop. One walk with the test in its node
  // loop, its branch never taken, made the Cornell box's intersect stage 25% slower on an H100
  // (7.23 against 5.78 ms at bc3982d; split: 6.01, benchmarks/RESULTS.md).
  if (r.parallel != 0) {
    detail::WalkWide<kMode, kNearest, true>(bvh, r, tMaxInOut, leaf, counters);
    return;
  }
  detail::WalkWide<kMode, kNearest, false>(bvh, r, tMaxInOut, leaf, counters);
#else
  detail::WalkWide<kMode, kNearest, true>(bvh, r, tMaxInOut, leaf, counters);
#endif
}

}  // namespace pt
