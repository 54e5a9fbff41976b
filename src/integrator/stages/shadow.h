// Stage 5, shadow: trace the shadow ray that shade queued (any hit ends it) and add the light
// sample's contribution when nothing blocks it.
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/path_state.h"
#include "src/scene/scene_view.h"

namespace pt {

// Occlusion only: the traversal stops at the first blocker (L, kInstanced, kHitTest as in
// IntersectPath).
template <BvhLayout L, bool kInstanced, bool kHitTest>
PT_HDI void TraceShadowRay(const SceneView& scene, PathState ps, uint32_t id, Counter* counters) {
  uint32_t flags = ps.flags[id];
  if (!(flags & kFlagShadow)) return;
  ps.flags[id] = flags & ~kFlagShadow;
  Ray ray{ps.shadowOrigin[id], ps.shadowDir[id]};
  TraversalCounters tc;
  bool occluded = SceneAny<L, kInstanced, kHitTest>(scene, ray, ps.shadowTMax[id], &tc);
  if (!occluded) ps.radiance[id] += ps.shadowRadiance[id];
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
    AddToCounter(&counters[kCounterShadowRays], 1);
  }
}

// TraceShadowRay for a flat scene in the wide layout as a resumable task (resumable_task.h).
template <bool kHitTest>
struct ShadowTask {
  SceneView scene;
  PathState ps;
  const uint32_t* queue;
  Counter* counters;

  struct State {
    uint32_t id;
    PrimLeaf<TraceMode::kAny, kHitTest> leaf;
    WideTraversal walk;
  };

  PT_HDI bool Start(State& st, uint32_t i) const {
    st.id = queue[i];
    const uint32_t flags = ps.flags[st.id];
    if (!(flags & kFlagShadow)) return false;
    ps.flags[st.id] = flags & ~kFlagShadow;
    const Ray ray{ps.shadowOrigin[st.id], ps.shadowDir[st.id]};
    st.leaf = PrimLeaf<TraceMode::kAny, kHitTest>(scene, ray);
    if (scene.primCount != 0 && st.walk.Start(SceneWideBvh(scene), ray, ps.shadowTMax[st.id]))
      return true;
    st.walk.nodesVisited = 0;  // nothing to walk: unoccluded
    Finish(st);
    return false;
  }

  PT_HDI bool Step(State& st) const {
    return st.walk.template Step<TraceMode::kAny>(SceneWideBvh(scene), st.leaf);
  }

  PT_HDI void Finish(State& st) const {
    if (st.leaf.prim == HitRecord::kNoHit) ps.radiance[st.id] += ps.shadowRadiance[st.id];
    if (counters) {
      AddToCounter(&counters[kCounterNodesVisited], st.walk.nodesVisited);
      AddToCounter(&counters[kCounterPrimsTested], st.leaf.tested);
      AddToCounter(&counters[kCounterTraversals], 1);
      AddToCounter(&counters[kCounterShadowRays], 1);
    }
  }
};

}  // namespace pt
