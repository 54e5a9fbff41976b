// Wide BVH traversal with pooled primitive tests (GPU, flat scenes; --prim-pool).
//
// In the per-ray walk (traverse_wide.h) each lane tests its own leaves' triangles, and the
// profile of that kernel shows why it is slow: the triangle tests are more than half of its
// instructions and run with 3-4 of 32 lanes busy (benchmarks/RESULTS.md, 2026-11-26). Here the
// lanes of a warp walk their nodes one per step as before, then test the primitives all of
// them found in that step together: entry j of the pooled list goes to the j-th lane, which
// reads the owning lane's ray with shuffles and reports its hit through a per-lane slot in
// shared memory. Each round keeps every lane busy while primitives remain. It pays on large
// scenes (1.18x per render on the Breakfast Room) and costs on small ones, whose walks are short
// (0.89x on the bunny Cornell): hence --prim-pool auto (flag_policy.h).
//
// Same hits as the per-ray walk: the closest hit is the smallest (t, tagIndex) of the tested
// primitives (traverse.h's rule), taken here with a 64-bit atomicMin on that key; a primitive
// tested later against a stale, larger tMax only costs time. The host has no warps, so it runs
// the per-ray walk (the callers in traverse.h choose).
#pragma once

#include "src/geometry/shapes.h"
#include "src/geometry/traverse_wide.h"

namespace pt {

// The pooled walk keeps one shared-memory slot per thread of a block of at most this many.
constexpr uint32_t kPoolMaxBlock = 128;

#if PT_IS_GPU_CODE && defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 800
#define PT_POOLED_LEAF_TESTS 1

namespace detail {

// Where testers report to the lane that owns a ray: the best key so far (t bits << 32 |
// tagIndex; any hit writes 0 for occlusion rays), then the primitive and uv of that key.
struct PoolSlots {
  unsigned long long key[kPoolMaxBlock];
  uint32_t prim[kPoolMaxBlock];
  float u[kPoolMaxBlock], v[kPoolMaxBlock];
};

__device__ inline PoolSlots& SharedPoolSlots() {
  __shared__ PoolSlots slots;
  return slots;
}

// What a lane knows of its own ray's result.
struct PoolBest {
  float tMax;
  uint32_t prim, tag;
  vec2 uv;
  __device__ static PoolBest None(float tMax) {
    PoolBest b;
    b.tMax = tMax;
    b.prim = HitRecord::kNoHit;
    b.tag = 0xffffffffu;
    b.uv = vec2(0.0f);
    return b;
  }
};

__device__ inline unsigned long long PoolKey(float t, uint32_t tag) {
  return (static_cast<unsigned long long>(__float_as_uint(t)) << 32) | tag;
}

// The pooled entries of one step: lane i of the team owns entries [prefix, prefix + count) of
// the list (its primitives primBase + the set bits of primMask, in bit order). Every lane of the
// team calls this, with or without primitives. Returns how many this lane's ray had tested.
template <TraceMode kMode, bool kHitTest>
__device__ inline uint32_t TestPooledPrims(const SceneView& s, uint32_t team, const Ray& ray,
                                           uint32_t primBase, uint32_t primMask,
                                           PoolBest* best) {
  const uint32_t lane = threadIdx.x & 31u, below = (1u << lane) - 1u;
  const uint32_t count = uint32_t(__popc(primMask));
  // Prefix sums by bit planes: a count is at most 24, five ballots.
  uint32_t prefix = 0, total = 0;
  for (uint32_t k = 0; k < 5; ++k) {
    const uint32_t plane = __ballot_sync(team, (count >> k) & 1u);
    prefix += uint32_t(__popc(plane & below)) << k;
    total += uint32_t(__popc(plane)) << k;
  }
  if (total == 0) return 0;  // the same for the whole team
  const uint32_t teamSize = uint32_t(__popc(team)), rank = uint32_t(__popc(team & below));
  const uint32_t warpBase = threadIdx.x & ~31u;
  PoolSlots& slots = SharedPoolSlots();
  for (uint32_t base = 0; base < total; base += teamSize) {
    // This lane's entries in the round, and where the round's owners start.
    const uint32_t first = max(prefix, base), end = min(prefix + count, base + teamSize);
    const bool owns = first < end;
    const uint32_t starts = __reduce_or_sync(team, owns ? 1u << (first - base) : 0u);
    const uint32_t owners = __ballot_sync(team, owns);
    const uint32_t entry = base + rank;
    const bool tests = entry < total;
    uint32_t src = lane;
    if (tests) src = __fns(owners, 0, int(__popc(starts & ((2u << rank) - 1u))));
    const Ray r{vec3(__shfl_sync(team, ray.o.x, src), __shfl_sync(team, ray.o.y, src),
                     __shfl_sync(team, ray.o.z, src)),
                vec3(__shfl_sync(team, ray.d.x, src), __shfl_sync(team, ray.d.y, src),
                     __shfl_sync(team, ray.d.z, src))};
    const float tMax = __shfl_sync(team, best->tMax, src);
    const bool hasHit = __shfl_sync(team, best->prim, src) != HitRecord::kNoHit;
    const uint32_t srcPrefix = __shfl_sync(team, prefix, src);
    const uint32_t srcMask = __shfl_sync(team, primMask, src);
    const uint32_t srcBase = __shfl_sync(team, primBase, src);
    bool hit = false;
    float t = 0.0f;
    uint32_t prim = 0;
    vec2 uv(0.0f);
    if (tests) {
      prim = srcBase + uint32_t(__fns(srcMask, 0, int(entry - srcPrefix) + 1));
      const float limit = hasHit ? NextFloatUp(tMax) : tMax;
      hit = IntersectPrim<kHitTest>(s, prim, r, TriangleRayData::Make(r.d), limit, &t, &uv);
    }
    // Most rounds find nothing: then no lane's ray changes and the slots stay untouched.
    if (!__any_sync(team, hit)) continue;
    if (owns) {
      slots.key[threadIdx.x] = kMode == TraceMode::kAny ? 1ull : PoolKey(best->tMax, best->tag);
      slots.prim[threadIdx.x] = HitRecord::kNoHit;
    }
    __syncwarp(team);
    const unsigned long long key =
        kMode == TraceMode::kAny ? 0ull : PoolKey(t, hit ? s.prims[prim].tagIndex : 0u);
    if (hit) atomicMin(&slots.key[warpBase + src], key);
    __syncwarp(team);
    if constexpr (kMode == TraceMode::kClosest) {
      // Of equal keys (one triangle referenced twice by spatial splits) the lowest index wins.
      const bool won = hit && slots.key[warpBase + src] == key;
      if (won) atomicMin(&slots.prim[warpBase + src], prim);
      __syncwarp(team);
      if (won && slots.prim[warpBase + src] == prim) {
        slots.u[warpBase + src] = uv.x;
        slots.v[warpBase + src] = uv.y;
      }
      __syncwarp(team);
      if (owns && slots.prim[threadIdx.x] != HitRecord::kNoHit) {  // a better hit came
        const unsigned long long k = slots.key[threadIdx.x];
        best->tMax = __uint_as_float(uint32_t(k >> 32));
        best->tag = uint32_t(k);
        best->prim = slots.prim[threadIdx.x];
        best->uv = vec2(slots.u[threadIdx.x], slots.v[threadIdx.x]);
      }
    } else {
      if (owns && slots.key[threadIdx.x] == 0ull) best->prim = 0;
    }
    __syncwarp(team);  // the slots are rewritten by the next round
  }
  return count;
}

// The walk: the lanes that called it together (the team) step through their trees one node at
// a time and test the primitives of each step together; a lane whose walk is over keeps taking
// part in the rounds until the whole team is done. kParallel: the node test checks parallel
// axes (wide_node_test.h); the team takes one copy for all its lanes (TraversePooled).
template <TraceMode kMode, bool kHitTest, bool kParallel>
__device__ inline void PooledWalk(const SceneView& s, uint32_t team, const Ray& ray,
                                  const WideRay& r, bool done, PoolBest* best,
                                  TraversalCounters* counters) {
  const WideBvh bvh = SceneWideBvh(s);
  // The per-ray walk's steps, without postponing: here every step's primitives are tested at
  // once, by the whole team.
  WideStack<kWideStackSize> stack;
  WideWalk<kWideStackSize> w(stack);
  uint32_t nodesVisited = 0, primsTested = 0;
  while (__any_sync(team, !done)) {
    w.primMask = 0;
    if (!done && !w.HasNode()) done = !w.Pop();
    if (!done) {
      ++nodesVisited;
      w.template VisitNext<false, kWideNearestFirst<kMode>, kParallel>(bvh.nodes, r, best->tMax);
    }
    primsTested += TestPooledPrims<kMode, kHitTest>(s, team, ray, w.primBase, w.primMask, best);
    if (kMode == TraceMode::kAny && best->prim != HitRecord::kNoHit) done = true;
  }
  if (counters) {
    counters->nodes += nodesVisited;
    counters->prims += primsTested;
  }
}

// Two copies of the walk, as Traverse's (traverse_wide.h): a team none of whose rays has a
// parallel axis (nearly every team) runs the one without parallel-axis code in its node loop.
// With only the other, the Breakfast Room's intersect and shadow stages (pooled) were 6-8%
// slower on an H100 than at bc3982d (benchmarks/RESULTS.md).
template <TraceMode kMode, bool kHitTest>
__device__ inline void TraversePooled(const SceneView& s, const Ray& ray, PoolBest* best,
                                      TraversalCounters* counters) {
  const uint32_t team = __activemask();
  const bool done = SceneWideBvh(s).nodeCount == 0 || !TraceableRay(ray);
  const WideRay r = MakeWideRay(ray);
  if (__any_sync(team, !done && r.parallel != 0)) {
    PooledWalk<kMode, kHitTest, true>(s, team, ray, r, done, best, counters);
  } else {
    PooledWalk<kMode, kHitTest, false>(s, team, ray, r, done, best, counters);
  }
}

}  // namespace detail

// Whether this launch can pool (a block small enough for the slots): the same for a whole
// kernel, so the team never splits over it.
__device__ inline bool CanPoolLeafTests() { return blockDim.x <= kPoolMaxBlock; }

template <bool kHitTest>
__device__ inline bool IntersectClosestPooled(const SceneView& s, const Ray& ray, float tMax,
                                              HitRecord* hit, TraversalCounters* counters) {
  detail::PoolBest best = detail::PoolBest::None(tMax);
  detail::TraversePooled<TraceMode::kClosest, kHitTest>(s, ray, &best, counters);
  hit->t = best.prim == HitRecord::kNoHit ? tMax : best.tMax;
  hit->prim = best.prim;
  hit->uv = best.prim == HitRecord::kNoHit ? vec2(0.0f) : best.uv;
  return best.prim != HitRecord::kNoHit;
}

template <bool kHitTest>
__device__ inline bool IntersectAnyPooled(const SceneView& s, const Ray& ray, float tMax,
                                          TraversalCounters* counters) {
  detail::PoolBest best = detail::PoolBest::None(tMax);
  detail::TraversePooled<TraceMode::kAny, kHitTest>(s, ray, &best, counters);
  return best.prim != HitRecord::kNoHit;
}

#endif  // PT_IS_GPU_CODE && sm_80+

}  // namespace pt
