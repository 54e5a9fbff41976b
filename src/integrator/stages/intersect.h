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
template <BvhLayout L, bool kInstanced, bool kHitTest>
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
  SceneClosest<L, kInstanced, kHitTest>(scene, ray, kInfinity, &hit, &tc);
  StoreHit(ps, id, hit, kInstanced);
  if (sort.keys) sort.keys[i] = MaterialSortKey(scene, sort.materialKeys, hit);
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
  }
}

// IntersectPath for a flat scene in the wide layout as a resumable task (resumable_task.h):
// the same query, one node a step, and the same writes.
template <bool kHitTest>
struct ClosestHitTask {
  SceneView scene;
  PathState ps;
  const uint32_t* queue;
  SortKeyOutput sort;
  Counter* counters;

  struct State {
    uint32_t id, i;
    PrimLeaf<TraceMode::kClosest, kHitTest> leaf;
    WideTraversal walk;
  };

  PT_HDI bool Start(State& st, uint32_t i) const {
    st.i = i;
    st.id = queue[i];
    if (!IsAlive(ps.flags[st.id])) {
      if (sort.keys) sort.keys[i] = scene.materialCount + 1;
      return false;
    }
    const Ray ray{ps.rayOrigin[st.id], ps.rayDir[st.id]};
    st.leaf = PrimLeaf<TraceMode::kClosest, kHitTest>(scene, ray);
    if (scene.primCount != 0 && st.walk.Start(SceneWideBvh(scene), ray, kInfinity)) return true;
    st.walk.tMax = kInfinity;  // nothing to walk: a miss
    st.walk.nodesVisited = 0;
    Finish(st);
    return false;
  }

  PT_HDI bool Step(State& st) const {
    return st.walk.template Step<TraceMode::kClosest>(SceneWideBvh(scene), st.leaf);
  }

  PT_HDI void Finish(State& st) const {
    const HitRecord hit{st.walk.tMax, st.leaf.prim, st.leaf.uv, kNoInstance};
    StoreHit(ps, st.id, hit, false);
    if (sort.keys) sort.keys[st.i] = MaterialSortKey(scene, sort.materialKeys, hit);
    if (counters) {
      AddToCounter(&counters[kCounterNodesVisited], st.walk.nodesVisited);
      AddToCounter(&counters[kCounterPrimsTested], st.leaf.tested);
      AddToCounter(&counters[kCounterTraversals], 1);
    }
  }
};

}  // namespace pt
