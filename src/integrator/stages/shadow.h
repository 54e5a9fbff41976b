// Stage 5, shadow: trace the shadow ray that shade queued (any hit ends it) and add the light
// sample's contribution when nothing blocks it.
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/path_state.h"
#include "src/scene/scene_view.h"

namespace pt {

// Occlusion only: the traversal stops at the first blocker (L, kInstanced, kHitTest as in
// IntersectPath).
template <BvhLayout L, bool kInstanced, bool kHitTest, bool kPooled = false>
PT_HDI void TraceShadowRay(const SceneView& scene, PathState ps, uint32_t id, Counter* counters) {
  uint32_t flags = ps.flags[id];
  if (!(flags & kFlagShadow)) return;
  ps.flags[id] = flags & ~kFlagShadow;
  Ray ray{ps.shadowOrigin[id], ps.shadowDir[id]};
  TraversalCounters tc;
  bool occluded = SceneAny<L, kInstanced, kHitTest, kPooled>(scene, ray, ps.shadowTMax[id], &tc);
  if (!occluded) ps.radiance[id] += ps.shadowRadiance[id];
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
    AddToCounter(&counters[kCounterShadowRays], 1);
  }
}

}  // namespace pt
