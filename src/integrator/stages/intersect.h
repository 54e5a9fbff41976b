// Stage 2, intersect: the closest hit of each live path's ray through the BVH, and the key the
// optional shading order sorts the queue by (src/integrator/shade_order.h).
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/path_state.h"
#include "src/scene/scene_view.h"

namespace pt {

// Where intersect writes sort keys: one per queue position, from the materials' keys (ranked
// by shade queue); escaped paths take materialCount, finished ones materialCount + 1. Null
// keys: no ordering this render.
struct SortKeyOutput {
  uint32_t* keys;
  const uint32_t* materialKeys;
};

// The key of the material a hit shades with (an instance's override where it has one).
PT_HDI uint32_t MaterialSortKey(const SceneView& scene, const uint32_t* materialKeys,
                                const HitRecord& hit) {
  if (hit.prim == HitRecord::kNoHit) return scene.materialCount;
  if (hit.instance != kNoInstance && scene.instances[hit.instance].material >= 0)
    return materialKeys[scene.instances[hit.instance].material];
  return materialKeys[scene.prims[hit.prim].material];
}

// Path id at queue position i. L is the scene's BVH layout (scene.bvhLayout), kInstanced
// whether it has instances (two levels), kHitTest whether a material asks for hit tests: one
// kernel per variant, so none pays for another's registers.
template <BvhLayout L, bool kInstanced, bool kHitTest, bool kPooled = false>
PT_HDI void IntersectPath(const SceneView& scene, PathState ps, uint32_t id, uint32_t i,
                          SortKeyOutput sort, Counter* counters) {
  if (!IsAlive(ps.flags[id])) {  // only without compaction do dead paths stay queued
    if (sort.keys) sort.keys[i] = scene.materialCount + 1;
    return;
  }
  Ray ray{ps.rayOrigin[id], ps.rayDir[id]};
  HitRecord hit;
  hit.prim = HitRecord::kNoHit;
  hit.t = kInfinity;
  hit.uv = vec2(0.0f);
  TraversalCounters tc;
  SceneClosest<L, kInstanced, kHitTest, kPooled>(scene, ray, kInfinity, &hit, &tc);
  StoreHit(ps, id, hit, kInstanced);
  if (sort.keys) sort.keys[i] = MaterialSortKey(scene, sort.materialKeys, hit);
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
  }
}

}  // namespace pt
