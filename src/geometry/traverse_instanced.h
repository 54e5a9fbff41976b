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

// One primitive of an instance's bottom level against the object-space ray: kClosest keeps the
// nearest (ties by (instance, tag)), kAny takes any. True when it was taken.
template <TraceMode kMode>
PT_HDI bool TestBottomPrim(const SceneView& s, uint32_t i, const Ray& ray,
                           const TriangleRayData& triRay, uint32_t instance, InstancedBest& best,
                           float* tMax) {
  ++best.tested;
  float t;
  vec2 uv;
  if (kMode == TraceMode::kAny) {
    if (!IntersectPrim(s, i, ray, triRay, *tMax, &t, &uv)) return false;
    best.prim = i;
    best.instance = instance;
    return true;
  }
  // Once there is a hit, also admit one at exactly its distance: the smaller key wins.
  float limit = best.Found() ? NextFloatUp(*tMax) : *tMax;
  if (!IntersectPrim(s, i, ray, triRay, limit, &t, &uv)) return false;
  uint32_t tag = s.prims[i].tagIndex;
  if (!(t < *tMax) && !best.Precedes(instance, tag)) return false;
  *tMax = t;
  best = InstancedBest{i, instance, tag, uv, best.tested};
  return true;
}

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
      if (!TestBottomPrim<kMode>(s, i, ray, triRay, instance, best, tMax)) continue;
      if (kMode == TraceMode::kAny) return true;
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
  InstancedBest& best;

  PT_HDI InstanceLeaf(const SceneView& scene, const Ray& r, TraversalCounters* c, InstancedBest& b)
      : s(scene), ray(r), counters(c), best(b) {}

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

// The wide layout's two levels in one loop over one stack: a top-level primitive enters its
// instance (the node's other instances and interior children wait on the stack, above which
// the instance's own groups go), and the walk returns to the top level when the stack is back
// to where it was. Hits, culling and their order are those of the nested walk (InstanceLeaf in
// a Traverse); but on the GPU the lanes of a warp, whichever level each is on, run the same
// node test together instead of the top level waiting for the others' whole bottom walks, and
// only one level's ray is live at a time.
constexpr int kTwoLevelStackCapacity = 2 * kWideStackCapacity + 2;

template <TraceMode kMode>
PT_HDI void TraverseInstancedWide(const SceneView& s, const Ray& worldRay, float* tMaxInOut,
                                  InstancedBest& best, TraversalCounters* counters) {
  if (!TraceableRay(worldRay)) return;
  const detail::WideRay worldR = detail::MakeWideRay(worldRay);
  float worldTMax = *tMaxInOut;
  // The level being walked. In an instance: its nodes, the object-space ray, distances less dt.
  const WideBvhNode* nodes = s.tlasWideNodes;
  Ray ray = worldRay;
  detail::WideRay r = worldR;
  TriangleRayData triRay{};
  float tMax = worldTMax, dt = 0.0f;
  int instanceStack = -1;  // the stack size on entering the current instance; -1: top level
  uint32_t instance = 0, primOffset = 0, nodesVisited = 0;
  bool instanceHit = false;
  detail::WideStack<kTwoLevelStackCapacity> stack;
  detail::WideWalk<kTwoLevelStackCapacity> w(stack);
  for (;;) {
    if (w.primMask == 0 && w.HasNode()) {
      ++nodesVisited;
      w.VisitNext(nodes, r, tMax);
    }
    if (instanceStack < 0 && w.primMask != 0) {  // enter the group's next instance
      const uint32_t bit = detail::LowestBit(w.primMask);
      const uint32_t rest = w.primMask & (w.primMask - 1u);
      if (w.HasNode()) w.Push(w.groupBase, w.groupMask);
      if (rest != 0) {
        w.Push(w.primBase, rest);
        ++w.postponed;
      }
      instance = s.instanceOrder[w.primBase + bit];
      w.primMask = 0;
      w.groupMask = 0;
      const Instance& inst = s.instances[instance];
      dt = 0.0f;
      ray = (inst.flags & kInstanceIdentity) ? worldRay : ObjectRay(inst, worldRay, &dt);
      if (TraceableRay(ray)) {
        r = detail::MakeWideRay(ray);
        triRay = TriangleRayData::Make(ray.d);
        tMax = worldTMax - dt;
        nodes = s.wideNodes + inst.nodeOffset;
        primOffset = inst.primOffset;
        instanceStack = w.stackSize;
        instanceHit = false;
        w.Restart();
      }
    }
    bool done = false;
    while (w.primMask != 0) {  // in an instance: its primitives
      const uint32_t bit = detail::LowestBit(w.primMask);
      w.primMask &= w.primMask - 1u;
      if (!TestBottomPrim<kMode>(s, primOffset + w.primBase + bit, ray, triRay, instance, best,
                                 &tMax))
        continue;
      instanceHit = true;
      if (kMode == TraceMode::kAny) done = true;
      if (done) break;
    }
    if (done) break;
    if (w.HasNode()) continue;
    if (w.stackSize == instanceStack) {  // the instance is done: back to the top level
      if (instanceHit) worldTMax = fminf(tMax + dt, worldTMax);
      nodes = s.tlasWideNodes;
      ray = worldRay;
      r = worldR;
      tMax = worldTMax;
      instanceStack = -1;
    }
    if (!w.Pop()) break;
  }
  *tMaxInOut = worldTMax;
  if (counters) counters->nodes += nodesVisited;
}

// Every instance's primitives against the world ray, into best: the wide layout in one loop, the
// binary one as a Traverse whose leaves walk their instances' trees.
template <BvhLayout L, TraceMode kMode>
PT_HDI void TraverseInstances(const SceneView& s, const Ray& ray, float* tMax, InstancedBest& best,
                              TraversalCounters* counters) {
  if (s.instanceCount == 0) return;
  if constexpr (L == BvhLayout::kWide) {
    TraverseInstancedWide<kMode>(s, ray, tMax, best, counters);
  } else {
    InstanceLeaf<L, kMode> leaf(s, ray, counters, best);
    Traverse<kMode>(TopLevelBvh<L>(s), ray, tMax, leaf, counters);
  }
}

// Nearest hit over every instance with 0 < t < tMax (as IntersectClosest in a flat scene),
// hit->instance naming the placement.
template <BvhLayout L>
PT_HDI bool IntersectClosestInstanced(const SceneView& s, const Ray& ray, float tMax,
                                      HitRecord* hit, TraversalCounters* counters) {
  InstancedBest best;
  float t = tMax;
  TraverseInstances<L, TraceMode::kClosest>(s, ray, &t, best, counters);
  if (counters) counters->prims += best.tested;
  hit->t = t;
  hit->prim = best.prim;
  hit->uv = best.uv;
  hit->instance = best.instance;
  return best.Found();
}

template <BvhLayout L>
PT_HDI bool IntersectAnyInstanced(const SceneView& s, const Ray& ray, float tMax,
                                  TraversalCounters* counters) {
  InstancedBest best;
  float t = tMax;
  TraverseInstances<L, TraceMode::kAny>(s, ray, &t, best, counters);
  if (counters) counters->prims += best.tested;
  return best.Found();
}

}  // namespace pt
