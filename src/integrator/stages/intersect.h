// Stage 2, intersect: the closest hit of each live path's ray through the BVH, and the key
// (material hit) that the optional sort orders the queue by.
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/path_state.h"
#include "src/scene/scene_view.h"

namespace pt {

// Misses sort after every material; an instance's override is the material it shades with.
PT_HDI uint32_t MaterialSortKey(const SceneView& scene, const HitRecord& hit) {
  if (hit.prim == HitRecord::kNoHit) return scene.materialCount;
  if (hit.instance != kNoInstance && scene.instances[hit.instance].material >= 0)
    return uint32_t(scene.instances[hit.instance].material);
  return scene.prims[hit.prim].material;
}

// L is the scene's BVH layout (scene.bvhLayout), kInstanced whether it has instances (two
// levels): one kernel per variant, so none pays for another's registers.
template <BvhLayout L, bool kInstanced>
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
  SceneClosest<L, kInstanced>(scene, ray, kInfinity, &hit, &tc);
  StoreHit(ps, id, hit, kInstanced);
  if (sortKey) *sortKey = MaterialSortKey(scene, hit);
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
  }
}

}  // namespace pt
