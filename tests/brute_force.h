// The reference every BVH test compares with: all primitives tested in index order.
#pragma once

#include "src/geometry/shapes.h"

namespace pt::test {

// Nearest primitive with 0 < t < tMax over s.prims, by brute force; of hits at the same
// distance the smallest PrimRef::tagIndex wins, as in traversal (traverse.h).
inline bool BruteForceClosest(const SceneView& s, const Ray& ray, float tMax, HitRecord* hit) {
  hit->prim = HitRecord::kNoHit;
  for (uint32_t i = 0; i < s.primCount; ++i) {
    float t;
    vec2 uv;
    const float limit = hit->prim == HitRecord::kNoHit ? tMax : NextFloatUp(tMax);
    if (!IntersectPrim(s, i, ray, limit, &t, &uv)) continue;
    if (!(t < tMax) && !(s.prims[i].tagIndex < s.prims[hit->prim].tagIndex)) continue;
    *hit = HitRecord{t, i, uv};
    tMax = t;
  }
  return hit->prim != HitRecord::kNoHit;
}

}  // namespace pt::test
