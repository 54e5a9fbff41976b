// BVH traversal: closest hit for extension rays, any hit for shadow rays. Iterative with a
// fixed-size stack (no allocation, no recursion), children visited front to back.
#pragma once

#include "src/geometry/aabb.h"
#include "src/geometry/interaction.h"
#include "src/geometry/shapes.h"
#include "src/scene/scene_view.h"

namespace pt {

// Deepest leaf BuildBvh makes (root = depth 0); a node deeper than this becomes a leaf whatever
// its size. Traversal pushes at most one sibling per ancestor of the node it is on, so the stack
// never holds more than kBvhMaxDepth entries. SAH trees of a few million primitives are ~30-45
// deep; only pathological inputs (e.g. geometrically spaced primitives) reach the cap.
constexpr int kBvhMaxDepth = 64;
constexpr int kBvhStackSize = kBvhMaxDepth;

namespace detail {

// One walk serves both queries; kAnyHit stops at the first accepted primitive. On return
// *tClosest/*primClosest/*uvClosest hold the nearest hit (primClosest = kNoHit if none).
template <bool kAnyHit>
PT_HDI void TraverseBvh(const SceneView& s, const Ray& ray, float* tClosest, uint32_t* primClosest,
                        vec2* uvClosest, TraversalCounters* counters) {
  *primClosest = HitRecord::kNoHit;
  if (s.nodeCount == 0 || s.primCount == 0) return;
  float tMax = *tClosest;
  const vec3 invDir(1.0f / ray.d.x, 1.0f / ray.d.y, 1.0f / ray.d.z);
  const TriangleRayData triRay = TriangleRayData::Make(ray.d);
  uint32_t nodesVisited = 0, primsTested = 0;

  // Entry distances travel with the stacked nodes so that a node farther than a hit found
  // meanwhile is skipped without reloading it.
  uint32_t stackNode[kBvhStackSize];
  float stackT[kBvhStackSize];
  int stackSize = 0;

  uint32_t node = 0;
  float tEntry;
  bool active =
      IntersectAabb(s.nodes[0].boundsMin, s.nodes[0].boundsMax, ray.o, invDir, tMax, &tEntry);
  while (active) {
    ++nodesVisited;
    const BvhNode& n = s.nodes[node];
    if (n.IsLeaf()) {
      for (uint32_t i = n.leftOrFirst, end = n.leftOrFirst + n.count; i < end; ++i) {
        ++primsTested;
        float t;
        vec2 uv;
        if (IntersectPrim(s, i, ray, triRay, tMax, &t, &uv)) {
          tMax = t;
          *primClosest = i;
          *uvClosest = uv;
          if (kAnyHit) break;
        }
      }
      if (kAnyHit && *primClosest != HitRecord::kNoHit) break;
    } else if (n.count == 0 && n.leftOrFirst != 0) {  // interior (a 0-count root is empty)
      uint32_t left = n.leftOrFirst;
      const BvhNode& l = s.nodes[left];
      const BvhNode& r = s.nodes[left + 1];
      float tl, tr;
      bool hitL = IntersectAabb(l.boundsMin, l.boundsMax, ray.o, invDir, tMax, &tl);
      bool hitR = IntersectAabb(r.boundsMin, r.boundsMax, ray.o, invDir, tMax, &tr);
      if (hitL && hitR) {
        bool leftFirst = tl <= tr;
        if (stackSize < kBvhStackSize) {  // always true for BuildBvh's trees (see above)
          stackNode[stackSize] = leftFirst ? left + 1 : left;
          stackT[stackSize] = leftFirst ? tr : tl;
          ++stackSize;
        }
        node = leftFirst ? left : left + 1;
        continue;
      }
      if (hitL || hitR) {
        node = hitL ? left : left + 1;
        continue;
      }
    }
    // Pop the nearest pending node that may still hold something closer than tMax.
    active = false;
    while (stackSize > 0) {
      --stackSize;
      if (stackT[stackSize] <= tMax * kAabbFarScale) {  // as IntersectAabb culls
        node = stackNode[stackSize];
        active = true;
        break;
      }
    }
  }
  *tClosest = tMax;
  if (counters) {
    counters->nodes += nodesVisited;
    counters->prims += primsTested;
  }
}

}  // namespace detail

// Nearest primitive with 0 < t < tMax. On a hit fills *hit (t, prim index into s.prims, uv as
// IntersectPrim gives it) and returns true; on a miss sets hit->prim = kNoHit, hit->t = tMax,
// hit->uv = 0. Counters (may be nullptr) are added to: nodes entered and primitives tested.
PT_HDI bool IntersectClosest(const SceneView& s, const Ray& ray, float tMax, HitRecord* hit,
                             TraversalCounters* counters) {
  float t = tMax;
  uint32_t prim;
  vec2 uv(0.0f);
  detail::TraverseBvh<false>(s, ray, &t, &prim, &uv, counters);
  hit->t = t;
  hit->prim = prim;
  hit->uv = uv;
  return prim != HitRecord::kNoHit;
}

// Whether any primitive has 0 < t < tMax (shadow rays); stops at the first one found.
PT_HDI bool IntersectAny(const SceneView& s, const Ray& ray, float tMax,
                         TraversalCounters* counters) {
  float t = tMax;
  uint32_t prim;
  vec2 uv(0.0f);
  detail::TraverseBvh<true>(s, ray, &t, &prim, &uv, counters);
  return prim != HitRecord::kNoHit;
}

}  // namespace pt
