// Stage 2, intersect: the closest hit of each live path's ray through the BVH, and the key
// (material hit) that the optional sort orders the queue by.
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/path_state.h"
#include "src/scene/scene_view.h"

namespace pt {

// Misses sort after every material.
PT_HDI uint32_t MaterialSortKey(const SceneView& scene, const HitRecord& hit) {
  return hit.prim == HitRecord::kNoHit ? scene.materialCount : scene.prims[hit.prim].material;
}

// L is the scene's BVH layout (scene.bvhLayout): one kernel per layout, so neither pays for the
// other's registers.
template <BvhLayout L>
PT_HDI void IntersectPath(const SceneView& scene, PathState ps, uint32_t id, uint32_t* sortKey,
                          Counter* counters) {
  if (!IsAlive(ps.flags[id])) {  // only without compaction do dead paths stay queued
    if (sortKey) *sortKey = scene.materialCount + 1;
    return;
  }
  Ray ray{ps.rayOrigin[id], ps.rayDir[id]};
  HitRecord hit;
  hit.prim = HitRecord::kNoHit;
  hit.t = kInfinity;
  hit.uv = vec2(0.0f);
  TraversalCounters tc;
  IntersectClosestIn<L>(scene, ray, kInfinity, &hit, &tc);
  ps.hit[id] = hit;
  if (sortKey) *sortKey = MaterialSortKey(scene, hit);
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
  }
}

}  // namespace pt
