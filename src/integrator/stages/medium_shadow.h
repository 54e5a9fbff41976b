// The shadow stage of scenes with media: a shadow ray's transmittance through the media it
// crosses (exact in homogeneous media, ratio or delta tracking in grids), passing through
// invisible surfaces (changing medium) and stopped by any other. Scenes without media run
// stages/shadow.h, untouched.
#pragma once

#include "src/integrator/stages/medium.h"

namespace pt {

// Multiplies st by the transmittance from ray.o to tMax, starting in medium m; false when
// something opaque is in the way or nothing gets through.
PT_HDI bool ShadowTransmittanceAlong(const SceneView& scene, const MediaView& mv, Ray ray,
                                     float tMax, int32_t m, int hero, vec3 rHat, MediumRng& rng,
                                     ShadowTransmittance* st, TraversalCounters* tc) {
  if (mv.invisibleCount == 0) {  // one medium all the way: any hit occludes
    if (IntersectAny<true>(scene, ray, tMax, tc)) return false;
    return m < 0 || EstimateTransmittance(mv, m, ray, tMax, hero, rHat, rng, st);
  }
  for (uint32_t n = 0; n <= kMaxInterfaceCrossings; ++n) {
    HitRecord hit;
    hit.prim = HitRecord::kNoHit;
    hit.t = tMax;
    hit.uv = vec2(0.0f);
    bool found = IntersectClosest<true>(scene, ray, tMax, &hit, tc);
    if (found && !IsInvisible(mv.InterfaceOf(hit.prim))) return false;
    float tSeg = found ? hit.t : tMax;
    if (m >= 0 && !EstimateTransmittance(mv, m, ray, tSeg, hero, rHat, rng, st)) return false;
    if (!found) return true;
    vec3 o;
    CrossInterface(scene, mv, ray, hit, &m, &o);
    tMax = tMax - hit.t;
    ray.o = o;
  }
  return false;
}

PT_HDI void TraceShadowRayInMedia(const SceneView& scene, const MediaView& mv,
                                  const WaveInfo& wave, PathState ps, MediaState ms, uint32_t id,
                                  Counter* counters) {
  uint32_t flags = ps.flags[id];
  if (!(flags & kFlagShadow)) return;
  ps.flags[id] = flags & ~kFlagShadow;
  RngKey key = wave.KeyOf(id);
  MediumRng rng(key, DepthOf(flags), kStreamShadow);
  ShadowTransmittance st;
  TraversalCounters tc;
  Ray ray{ps.shadowOrigin[id], ps.shadowDir[id]};
  if (ShadowTransmittanceAlong(scene, mv, ray, ps.shadowTMax[id],
                               int32_t(ms.shadowMedium[id]) - 1, HeroChannel(key), ms.rHat[id],
                               rng, &st, &tc))
    ps.radiance[id] += ps.shadowRadiance[id] * st.tr;
  if (counters) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
    AddToCounter(&counters[kCounterTraversals], 1);
    AddToCounter(&counters[kCounterShadowRays], 1);
  }
}

}  // namespace pt
