// Stage 3 of scenes with media, between intersect and shade: along each path's traced segment,
// delta tracking in the medium the path is in (src/media/tracking.h). A real scattering event
// is shaded here (next-event estimation through the phase function, a phase-sampled
// continuation) and its hit marked kMediumVertex so that shade skips it; absorption ends the
// path; a path that crosses an invisible surface (the "interface" material) changes medium and
// is traced on from there, so shade only ever sees real surfaces. Scenes without media never
// run or compile this stage.
#pragma once

#include "src/geometry/traverse.h"
#include "src/integrator/media_state.h"
#include "src/integrator/path_state.h"
#include "src/integrator/stages/shade.h"
#include "src/integrator/wave.h"
#include "src/lights/light_sample.h"
#include "src/media/tracking.h"

namespace pt {

// PathHit::prim of a path whose vertex is a scattering event in a medium (shade skips it).
constexpr uint32_t kMediumVertex = 0xfffffffeu;
// Invisible surfaces one segment may cross before the path is given up (nested bounds).
constexpr uint32_t kMaxInterfaceCrossings = 64;

// The medium beyond the invisible surface a segment's ray hit, and where the ray goes on
// (past the surface's error bounds). hit.t is along `ray`.
PT_HDI void CrossInterface(const SceneView& scene, const MediaView& mv, const Ray& ray,
                           const HitRecord& hit, int32_t* medium, vec3* origin) {
  SurfaceInteraction si = MakeInteraction(scene, ray, hit);
  *medium = MediumAfter(mv.InterfaceOf(hit.prim), si.ng, ray.d, *medium);
  *origin = OffsetRayOrigin(si.p, si.pError, si.ng, ray.d);
}

PT_HDI bool IsInvisibleHit(const MediaView& mv, const HitRecord& hit) {
  return hit.prim != HitRecord::kNoHit && IsInvisible(mv.InterfaceOf(hit.prim));
}

// Beer-Lambert attenuation of a dielectric the path is inside (shade applies it at surfaces).
PT_HDI vec3 GlassAttenuation(const SceneView& scene, uint32_t flags, float distance) {
  int32_t glass = MediumOf(flags);
  if (glass < 0) return vec3(1.0f);
  vec3 sigma = scene.materials[glass].absorption;
  return IsBlack(sigma) ? vec3(1.0f) : glm::exp(-sigma * distance);
}

// The light sample of a medium vertex: phase function against light sampling (MIS).
PT_HDI bool QueueMediumLightSample(const SceneView& scene, const IntegratorParams& params,
                                   vec3 p, vec3 d, float g, vec3 beta, vec4 u, PathState ps,
                                   uint32_t id) {
  LightLiSample ls;
  if (!SampleLightLi<true>(scene, p, u.x, vec2(u.y, u.z), &ls) || !(ls.pdf > 0.0f) ||
      IsBlack(ls.L))
    return false;
  float phase = HenyeyGreenstein(glm::dot(d, ls.wi), g);
  float weight = 1.0f;
  if (!ls.isDelta && params.kind == IntegratorKind::kMis) weight = PowerHeuristic(ls.pdf, phase);
  ps.shadowOrigin[id] = p;
  ps.shadowDir[id] = ls.wi;
  ps.shadowTMax[id] = ls.isInfinite ? kInfinity
                                    : glm::length(ls.pLight - p) * (1.0f - kShadowEpsilon);
  ps.shadowRadiance[id] = beta * ls.L * (phase * weight / ls.pdf);
  return true;
}

// What a path brings to a real scattering event.
struct MediumVertex {
  uint32_t flags;
  int32_t medium;
  vec3 p, d;
  float distance;  // from the ray's origin (the feature buffers' depth)
  vec3 beta, radiance, rHat;
};

// A real scattering event: next-event estimation, then the phase-sampled continuation with
// Russian roulette, as ShadeSurface does at a surface.
PT_HDI void ScatterInMedium(const SceneView& scene, const MediaView& mv,
                            const IntegratorParams& params, const WaveInfo& wave, PathState ps,
                            MediaState ms, uint32_t id, MediumVertex v) {
  const uint32_t depth = DepthOf(v.flags);
  const Medium& med = mv.media[v.medium];
  if (params.featureBuffers && depth == 0) {
    vec3 sigmaT = med.sigmaA + med.sigmaS;
    WriteFeatures(ps, id, med.sigmaS / glm::max(sigmaT, vec3(1e-30f)), vec3(0.0f), v.distance);
    RecordSeenEmission(ps, id, true, vec3(0.0f));  // a medium's light is filtered
  }
  ps.hit[id] = PathHit{v.distance, kMediumVertex, vec2(0.0f)};
  ms.rHat[id] = v.rHat;
  ms.medium[id] = uint32_t(v.medium + 1);
  if (int(depth) >= params.maxDepth) {
    TerminatePath(ps, id, v.flags, v.radiance);
    return;
  }
  RngKey key = wave.KeyOf(id);
  uint32_t flags = (v.flags & ~(kFlagSpecular | kDepthMask | kFlagShadow)) | (depth + 1);
  if (params.kind != IntegratorKind::kBsdf && params.Counts(depth + 1) &&
      QueueMediumLightSample(scene, params, v.p, v.d, med.g, v.beta,
                             key.Draw4(depth, kDimLight), ps, id)) {
    flags |= kFlagShadow;
    ms.shadowMedium[id] = uint32_t(v.medium + 1);
  }
  vec4 u = key.Draw4(depth, kDimBsdf);
  float pdf;
  vec3 wi = SampleHenyeyGreenstein(v.d, med.g, vec2(u.y, u.z), &pdf);  // weight p / pdf = 1
  bool alive = pdf > 0.0f;
  if (alive && int(depth) >= params.rrDepth) {
    float q = fmaxf(0.0f, 1.0f - MaxComponent(v.beta));
    if (u.w < q) alive = false;
    else v.beta /= 1.0f - q;
  }
  ps.throughput[id] = v.beta;
  ps.radiance[id] = v.radiance;
  ps.flags[id] = alive ? flags : (flags & ~kFlagAlive);
  if (!alive) return;
  ps.prevPdf[id] = pdf;
  ps.rayOrigin[id] = v.p;
  ps.rayDir[id] = wi;
}

// The next hit past an invisible surface, its distance counted from the path's ray origin
// (tBase: where the new segment starts).
PT_HDI HitRecord TraceOnFrom(const SceneView& scene, vec3 o, vec3 d, float tBase,
                             TraversalCounters* tc) {
  HitRecord hit;
  hit.prim = HitRecord::kNoHit;
  hit.t = kInfinity;
  hit.uv = vec2(0.0f);
  IntersectClosest<true>(scene, Ray{o, d}, kInfinity, &hit, tc);
  if (hit.prim != HitRecord::kNoHit) hit.t += tBase;
  return hit;
}

// Path id's medium stage. A path's throughput, radiance and rHat are written here at depth 0
// (generate leaves them alone), so shade reads them at every depth in media scenes.
PT_HDI void SampleMediumPath(const SceneView& scene, const MediaView& mv,
                             const IntegratorParams& params, const WaveInfo& wave, PathState ps,
                             MediaState ms, uint32_t id, Counter* counters) {
  const uint32_t flags = ps.flags[id];
  if (!IsAlive(flags)) return;
  const uint32_t depth = DepthOf(flags);
  const bool instanced = scene.instanceCount != 0;
  vec3 beta(1.0f), radiance(0.0f), rHat(1.0f);
  int32_t m = mv.cameraMedium;
  if (depth > 0) {
    beta = ps.throughput[id];
    radiance = ps.radiance[id];
    rHat = ms.rHat[id];
    m = int32_t(ms.medium[id]) - 1;
  }
  HitRecord hit = LoadHit(ps, id, instanced);
  bool crossing = IsInvisibleHit(mv, hit);
  if (m < 0 && !crossing) {  // vacuum up to a real surface (or out of the scene)
    if (depth == 0) {
      ps.throughput[id] = beta;
      ps.radiance[id] = radiance;
      ms.rHat[id] = rHat;
      ms.medium[id] = 0;
    }
    return;
  }
  const Ray ray{ps.rayOrigin[id], ps.rayDir[id]};
  RngKey key = wave.KeyOf(id);
  const int hero = HeroChannel(key);
  MediumRng rng(key, depth, kStreamPath);
  vec3 o = ray.o;
  float tBase = 0.0f;
  TraversalCounters tc;
  for (uint32_t n = 0;; ++n) {
    if (m >= 0) {
      float tSeg = hit.prim == HitRecord::kNoHit ? kInfinity : hit.t - tBase;
      TrackResult r = DeltaTrack(mv, m, Ray{o, ray.d}, tSeg, hero, rng, &beta, &rHat,
                                 params.Counts(depth), &radiance);
      if (r.event == MediumEvent::kAbsorbed) {
        if (params.featureBuffers && depth == 0) {
          WriteFeatures(ps, id, vec3(0.0f), vec3(0.0f), tBase + r.t);
          RecordSeenEmission(ps, id, true, vec3(0.0f));
        }
        TerminatePath(ps, id, flags, radiance);
        return;
      }
      if (r.event == MediumEvent::kScattered) {
        beta *= GlassAttenuation(scene, flags, tBase + r.t);
        ScatterInMedium(scene, mv, params, wave, ps, ms, id,
                        MediumVertex{flags, m, o + r.t * ray.d, ray.d, tBase + r.t, beta,
                                     radiance, rHat});
        return;
      }
    }
    if (!crossing) break;
    if (n >= kMaxInterfaceCrossings) {
      if (params.featureBuffers && depth == 0) {
        WriteFeatures(ps, id, vec3(0.0f), vec3(0.0f), hit.t);
        RecordSeenEmission(ps, id, true, vec3(0.0f));
      }
      TerminatePath(ps, id, flags, radiance);
      return;
    }
    HitRecord local = hit;
    local.t = hit.t - tBase;
    CrossInterface(scene, mv, Ray{o, ray.d}, local, &m, &o);
    tBase = glm::length(o - ray.o);
    hit = TraceOnFrom(scene, o, ray.d, tBase, &tc);
    crossing = IsInvisibleHit(mv, hit);
  }
  StoreHit(ps, id, hit, instanced);
  ps.throughput[id] = beta;
  ps.radiance[id] = radiance;
  ms.rHat[id] = rHat;
  ms.medium[id] = uint32_t(m + 1);
  if (counters && tc.nodes) {
    AddToCounter(&counters[kCounterNodesVisited], tc.nodes);
    AddToCounter(&counters[kCounterPrimsTested], tc.prims);
  }
}

}  // namespace pt
