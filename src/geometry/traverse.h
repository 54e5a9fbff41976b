// Scene ray queries: closest hit for extension rays, any hit (occlusion) for shadow rays, over
// either node layout (--bvh binary|wide), with the leaf callback for scene primitives.
//
// Building blocks for other traversals (e.g. a two-level one):
//   Traverse<TraceMode>(BinaryBvh or WideBvh, ray, &tMax, leaf, counters)   one BVH level
//   PrimLeaf<TraceMode>                                                    scene primitives
// with the leaf-callback contract of traverse_binary.h.
//
// The closest hit does not depend on the order in which nodes are visited: of hits at exactly
// the same distance, the primitive with the smallest PrimRef::tagIndex (the shape's identity,
// not its BVH position) wins. So both layouts, and every builder, give the same hit.
#pragma once

#include <type_traits>

#include "src/geometry/shapes.h"
#include "src/geometry/traverse_binary.h"
#include "src/geometry/traverse_instanced.h"
#include "src/geometry/traverse_wide.h"
#include "src/geometry/traverse_wide_pooled.h"

namespace pt {

// Tests s.prims[first, first + count) with IntersectPrim<kHitTest>. kClosest keeps the nearest
// accepted primitive (ties by tagIndex); kAny stops at the first.
template <TraceMode kMode, bool kHitTest = true>
struct PrimLeaf {
  const SceneView& s;
  const Ray& ray;
  TriangleRayData triRay;
  uint32_t prim = HitRecord::kNoHit;
  vec2 uv = vec2(0.0f);
  uint32_t tested = 0;

  PT_HDI PrimLeaf(const SceneView& scene, const Ray& r)
      : s(scene), ray(r), triRay(TriangleRayData::Make(r.d)) {}

  PT_HDI bool operator()(uint32_t first, uint32_t count, float* tMax) {
    bool found = false;
    for (uint32_t i = first, end = first + count; i < end; ++i) {
      ++tested;
      float t;
      vec2 hitUv;
      if (kMode == TraceMode::kAny) {
        if (!IntersectPrim<kHitTest>(s, i, ray, triRay, *tMax, &t, &hitUv)) continue;
        prim = i;
        return true;
      }
      // Once there is a hit, also admit one at exactly its distance: the smaller key wins.
      float limit = prim == HitRecord::kNoHit ? *tMax : NextFloatUp(*tMax);
      if (!IntersectPrim<kHitTest>(s, i, ray, triRay, limit, &t, &hitUv)) continue;
      if (!(t < *tMax) && !(s.prims[i].tagIndex < s.prims[prim].tagIndex)) continue;
      *tMax = t;
      prim = i;
      uv = hitUv;
      found = true;
    }
    return found;
  }
};

// One level over the scene's own BVH in layout L.
template <BvhLayout L, TraceMode kMode, typename LeafFn>
PT_HDI void TraverseScene(const SceneView& s, const Ray& ray, float* tMax, LeafFn& leaf,
                          TraversalCounters* counters) {
  if (s.primCount == 0) return;
  if constexpr (L == BvhLayout::kWide) {
    Traverse<kMode>(SceneWideBvh(s), ray, tMax, leaf, counters);
  } else {
    Traverse<kMode>(SceneBinaryBvh(s), ray, tMax, leaf, counters);
  }
}

// Nearest primitive with 0 < t < tMax. On a hit fills *hit (t, prim index into s.prims, uv as
// IntersectPrim gives it) and returns true; on a miss sets hit->prim = kNoHit, hit->t = tMax,
// hit->uv = 0. Counters (may be nullptr) are added to: nodes entered and primitives tested.
template <BvhLayout L, bool kHitTest = true, bool kPooled = false>
PT_HDI bool IntersectClosestIn(const SceneView& s, const Ray& ray, float tMax, HitRecord* hit,
                               TraversalCounters* counters) {
#ifdef PT_POOLED_LEAF_TESTS
  if constexpr (L == BvhLayout::kWide && kPooled) {
    if (CanPoolLeafTests()) return IntersectClosestPooled<kHitTest>(s, ray, tMax, hit, counters);
  }
#endif
  PrimLeaf<TraceMode::kClosest, kHitTest> leaf(s, ray);
  float t = tMax;
  TraverseScene<L, TraceMode::kClosest>(s, ray, &t, leaf, counters);
  if (counters) counters->prims += leaf.tested;
  hit->t = t;
  hit->prim = leaf.prim;
  hit->uv = leaf.uv;
  return leaf.prim != HitRecord::kNoHit;
}

// Whether any primitive has 0 < t < tMax (shadow rays); stops at the first one found.
template <BvhLayout L, bool kHitTest = true, bool kPooled = false>
PT_HDI bool IntersectAnyIn(const SceneView& s, const Ray& ray, float tMax,
                           TraversalCounters* counters) {
#ifdef PT_POOLED_LEAF_TESTS
  if constexpr (L == BvhLayout::kWide && kPooled) {
    if (CanPoolLeafTests()) return IntersectAnyPooled<kHitTest>(s, ray, tMax, counters);
  }
#endif
  PrimLeaf<TraceMode::kAny, kHitTest> leaf(s, ray);
  float t = tMax;
  TraverseScene<L, TraceMode::kAny>(s, ray, &t, leaf, counters);
  if (counters) counters->prims += leaf.tested;
  return leaf.prim != HitRecord::kNoHit;
}

// The scene's query in layout L, over the two levels when kInstanced (a scene with instances)
// or the one flat BVH otherwise: each a kernel variant of its own, so a flat scene runs exactly
// the single-level code. kHitTest: whether some material asks for a hit test (alpha, culling);
// a scene without one runs traversal without that code.
template <BvhLayout L, bool kInstanced, bool kHitTest = true, bool kPooled = false>
PT_HDI bool SceneClosest(const SceneView& s, const Ray& ray, float tMax, HitRecord* hit,
                         TraversalCounters* counters) {
  if constexpr (kInstanced) return IntersectClosestInstanced<L, kHitTest>(s, ray, tMax, hit, counters);
  else return IntersectClosestIn<L, kHitTest, kPooled>(s, ray, tMax, hit, counters);
}

template <BvhLayout L, bool kInstanced, bool kHitTest = true, bool kPooled = false>
PT_HDI bool SceneAny(const SceneView& s, const Ray& ray, float tMax, TraversalCounters* counters) {
  if constexpr (kInstanced) return IntersectAnyInstanced<L, kHitTest>(s, ray, tMax, counters);
  else return IntersectAnyIn<L, kHitTest, kPooled>(s, ray, tMax, counters);
}

// Calls f(layout, instanced) with the view's layout and structure (flat or two-level) as
// std::integral_constant values, the choice SceneClosest and SceneAny take at compile time
// (and the integrator's kernel variants, wavefront.h); returns what f returns.
template <typename F>
PT_HDI decltype(auto) ForSceneStructure(const SceneView& s, F&& f) {
  using Wide = std::integral_constant<BvhLayout, BvhLayout::kWide>;
  using Binary = std::integral_constant<BvhLayout, BvhLayout::kBinary>;
  const bool wide = s.bvhLayout == BvhLayout::kWide;
  using Two = std::true_type;
  using Flat = std::false_type;
  if (s.instanceCount != 0) return wide ? f(Wide{}, Two{}) : f(Binary{}, Two{});
  return wide ? f(Wide{}, Flat{}) : f(Binary{}, Flat{});
}

// The scene's queries in the layout and structure the view names (a run-time choice; stages
// instantiate per variant). kHitTest = false: no material asks for a hit test.
template <bool kHitTest = true>
PT_HDI bool IntersectClosest(const SceneView& s, const Ray& ray, float tMax, HitRecord* hit,
                             TraversalCounters* counters) {
  hit->instance = kNoInstance;
  return ForSceneStructure(s, [&](auto layout, auto instanced) {
    return SceneClosest<decltype(layout)::value, decltype(instanced)::value, kHitTest>(
        s, ray, tMax, hit, counters);
  });
}

template <bool kHitTest = true>
PT_HDI bool IntersectAny(const SceneView& s, const Ray& ray, float tMax,
                         TraversalCounters* counters) {
  return ForSceneStructure(s, [&](auto layout, auto instanced) {
    return SceneAny<decltype(layout)::value, decltype(instanced)::value, kHitTest>(s, ray, tMax,
                                                                                   counters);
  });
}

}  // namespace pt
