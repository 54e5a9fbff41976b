// The shade stage of scenes with media: ShadeSurface and ShadeEscaped as every scene runs
// them, around the media's bookkeeping. Paths that scattered in a medium were shaded by the
// medium stage; a path that leaves a surface across a medium interface enters the medium on
// the side its new ray (and its shadow ray) goes.
#pragma once

#include "src/integrator/stages/medium.h"

namespace pt {

// After shading at a surface: the medium of the continuation and of the shadow ray.
PT_HDI void UpdateSurfaceMedia(const SceneView& scene, const MediaView& mv, PathState ps,
                               MediaState ms, uint32_t id, const Ray& ray, const HitRecord& hit) {
  uint32_t iface = mv.InterfaceOf(hit.prim);
  uint32_t flags = ps.flags[id];
  if (!IsTransition(iface)) {
    if (flags & kFlagShadow) ms.shadowMedium[id] = ms.medium[id];
    return;
  }
  int32_t current = int32_t(ms.medium[id]) - 1;
  vec3 ng = MakeInteraction(scene, ray, hit).ng;
  if (flags & kFlagShadow)
    ms.shadowMedium[id] = uint32_t(MediumAfter(iface, ng, ps.shadowDir[id], current) + 1);
  if (IsAlive(flags)) ms.medium[id] = uint32_t(MediumAfter(iface, ng, ps.rayDir[id], current) + 1);
}

// ShadePath for scenes with media (feature class C, environment-map code kMap).
template <FeatureClass C, bool kMap>
PT_HDI void ShadeMediumScenePath(const SceneView& scene, const MediaView& mv,
                                 const IntegratorParams& params, const WaveInfo& wave,
                                 PathState ps, MediaState ms, uint32_t id) {
  uint32_t flags = ps.flags[id];
  if (!IsAlive(flags)) return;
  HitRecord hit = LoadHit(ps, id, scene.instanceCount != 0);
  if (hit.prim == kMediumVertex) return;
  PathVertex v{flags,
               DepthOf(flags),
               hit,
               Ray{ps.rayOrigin[id], ps.rayDir[id]},
               ps.throughput[id],
               ps.radiance[id],
               ps.prevPdf[id]};
  if constexpr (kHasMedia<C>) v.beta *= GlassAttenuation(scene, flags, hit.t);
  if (hit.prim == HitRecord::kNoHit) {
    ShadeEscaped<kMap>(scene, params, ps, id, v);
    return;
  }
  ShadeSurface<C, kAnyQueue, kMap, false>(scene, params, wave, ps, id, v);
  UpdateSurfaceMedia(scene, mv, ps, ms, id, v.ray, hit);
}

}  // namespace pt
