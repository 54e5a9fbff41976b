// Two-level traversal for scenes with instances: the top level is a BVH over the instances'
// world bounds; its leaf callback moves the ray into each instance's object space and walks
// that mesh's own BVH (the bottom level). Both levels use the scene's layout (--bvh), through
// the single-level Traverse of traverse_binary.h / traverse_wide.h.
//
// The closest hit does not depend on the order of visits: of hits at exactly the same
// distance, the smaller (instance, PrimRef::tagIndex) wins, as tagIndex alone does in a flat
// scene. An identity instance (the world-space primitives, or a mesh placed as it is) sees the
// world ray unchanged, so its hits are bit for bit those of the flat scene.
#pragma once

#include "src/geometry/instance.h"
#include "src/geometry/shapes.h"
#include "src/geometry/traverse_binary.h"
#include "src/geometry/traverse_wide.h"

namespace pt {

// The bottom level of an instance and the top level, in layout L. A bottom level is never empty
// (meshes without triangles are not placed), so its node count is only a non-zero marker.
template <BvhLayout L>
PT_HDI auto InstanceBvh(const SceneView& s, const Instance& inst) {
  if constexpr (L == BvhLayout::kWide) return WideBvh{s.wideNodes + inst.nodeOffset, 1u};
  else return BinaryBvh{s.nodes + inst.nodeOffset, 1u};
}

template <BvhLayout L>
PT_HDI auto TopLevelBvh(const SceneView& s) {
  if constexpr (L == BvhLayout::kWide) return WideBvh{s.tlasWideNodes, s.tlasNodeCount};
  else return BinaryBvh{s.tlasNodes, s.tlasNodeCount};
}

// The nearest hit over all instances so far (or the first, for any-hit queries).
struct InstancedBest {
  uint32_t prim = HitRecord::kNoHit;
  uint32_t instance = kNoInstance;
  uint32_t tag = 0;  // prims[prim].tagIndex
  vec2 uv = vec2(0.0f);
  uint32_t tested = 0;

  PT_HDI bool Found() const { return prim != HitRecord::kNoHit; }
  // Whether (instance, tag) wins a tie against the best hit.
  PT_HDI bool Precedes(uint32_t inst, uint32_t t) const {
    return inst < instance || (inst == instance && t < tag);
  }
};

// Bottom-level leaf callback: the mesh's primitives from primOffset, against the object-space ray.
template <TraceMode kMode>
struct BottomLeaf {
  const SceneView& s;
  const Ray& ray;
  TriangleRayData triRay;
  uint32_t primOffset;
  uint32_t instance;
  InstancedBest& best;

  PT_HDI BottomLeaf(const SceneView& scene, const Ray& r, uint32_t offset, uint32_t inst,
                    InstancedBest& b)
      : s(scene), ray(r), triRay(TriangleRayData::Make(r.d)), primOffset(offset), instance(inst),
        best(b) {}

  PT_HDI bool operator()(uint32_t first, uint32_t count, float* tMax) {
    bool found = false;
    for (uint32_t i = primOffset + first, end = i + count; i < end; ++i) {
      ++best.tested;
      float t;
      vec2 uv;
      if (kMode == TraceMode::kAny) {
        if (!IntersectPrim(s, i, ray, triRay, *tMax, &t, &uv)) continue;
        best.prim = i;
        best.instance = instance;
        return true;
      }
      // Once there is a hit, also admit one at exactly its distance: the smaller key wins.
      float limit = best.Found() ? NextFloatUp(*tMax) : *tMax;
      if (!IntersectPrim(s, i, ray, triRay, limit, &t, &uv)) continue;
      uint32_t tag = s.prims[i].tagIndex;
      if (!(t < *tMax) && !best.Precedes(instance, tag)) continue;
      *tMax = t;
      best = InstancedBest{i, instance, tag, uv, best.tested};
      found = true;
    }
    return found;
  }
};

// Top-level leaf callback: each instance of the leaf, its bottom level walked in object space.
template <BvhLayout L, TraceMode kMode>
struct InstanceLeaf {
  const SceneView& s;
  const Ray& ray;
  TraversalCounters* counters;
  InstancedBest best;

  PT_HDI InstanceLeaf(const SceneView& scene, const Ray& r, TraversalCounters* c)
      : s(scene), ray(r), counters(c) {}

  PT_HDI bool operator()(uint32_t first, uint32_t count, float* tMax) {
    bool found = false;
    for (uint32_t slot = first; slot < first + count; ++slot) {
      uint32_t id = s.instanceOrder[slot];
      const Instance& inst = s.instances[id];
      float dt = 0.0f;
      Ray r = (inst.flags & kInstanceIdentity) ? ray : ObjectRay(inst, ray, &dt);
      float t = *tMax - dt;
      uint32_t before = best.prim;
      uint32_t beforeInstance = best.instance;
      BottomLeaf<kMode> leaf(s, r, inst.primOffset, id, best);
      Traverse<kMode>(InstanceBvh<L>(s, inst), r, &t, leaf, counters);
      if (best.prim == before && best.instance == beforeInstance) continue;
      if (kMode == TraceMode::kAny) return true;
      *tMax = fminf(t + dt, *tMax);
      found = true;
    }
    return found;
  }
};

// Nearest hit over every instance with 0 < t < tMax (as IntersectClosest in a flat scene),
// hit->instance naming the placement.
template <BvhLayout L>
PT_HDI bool IntersectClosestInstanced(const SceneView& s, const Ray& ray, float tMax,
                                      HitRecord* hit, TraversalCounters* counters) {
  InstanceLeaf<L, TraceMode::kClosest> leaf(s, ray, counters);
  float t = tMax;
  if (s.instanceCount != 0) Traverse<TraceMode::kClosest>(TopLevelBvh<L>(s), ray, &t, leaf, counters);
  if (counters) counters->prims += leaf.best.tested;
  hit->t = t;
  hit->prim = leaf.best.prim;
  hit->uv = leaf.best.uv;
  hit->instance = leaf.best.instance;
  return leaf.best.Found();
}

template <BvhLayout L>
PT_HDI bool IntersectAnyInstanced(const SceneView& s, const Ray& ray, float tMax,
                                  TraversalCounters* counters) {
  InstanceLeaf<L, TraceMode::kAny> leaf(s, ray, counters);
  float t = tMax;
  if (s.instanceCount != 0) Traverse<TraceMode::kAny>(TopLevelBvh<L>(s), ray, &t, leaf, counters);
  if (counters) counters->prims += leaf.best.tested;
  return leaf.best.Found();
}

}  // namespace pt
