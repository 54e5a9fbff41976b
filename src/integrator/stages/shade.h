// Stage 4, shade: at each path's hit, add emission (weighted by MIS against light sampling),
// queue one shadow ray for next-event estimation, then sample the BSDF for the next ray, with
// Russian roulette. The whole integrator's light transport lives here.
#pragma once

#include "src/core/ray.h"
#include "src/core/sampling.h"
#include "src/geometry/shapes.h"
#include "src/integrator/path_state.h"
#include "src/integrator/wave.h"
#include "src/lights/light_sample.h"
#include "src/integrator/stages/bsdf_variant.h"
#include "src/integrator/stages/normal_fold.h"
#include "src/materials/shading_normal.h"
#include "src/integrator/stages/light_receiver.h"
#include "src/scene/scene_view.h"

namespace pt {

// Shadow rays stop this fraction short of the light point, so they never hit the light's own
// surface; relative to the distance, hence independent of the scene's scale (as pbrt-v4).
constexpr float kShadowEpsilon = 1e-4f;

// Weight of emission found by a BSDF-sampled ray, given the light-sampling pdf of the same
// direction; NEE covers the rest of that light's contribution.
PT_HDI float EmitterHitWeight(IntegratorKind kind, uint32_t flags, float prevPdf, float lightPdf) {
  bool direct = (flags & kFlagSpecular) != 0;  // camera ray or after a delta lobe
  switch (kind) {
    case IntegratorKind::kBsdf: return 1.0f;
    case IntegratorKind::kNee: return direct ? 1.0f : 0.0f;
    case IntegratorKind::kMis:
    default: return direct ? 1.0f : PowerHeuristic(prevPdf, lightPdf);
  }
}

// What a ray that leaves the scene along unit w gathers, each light at infinity weighted by
// MIS against its own light-sampling pdf: the constant background, the environment map and
// the directional lights with a cone (a sun disk). Delta directional lights cannot be hit.
template <bool kMap>
PT_HDI vec3 EscapedRadiance(const SceneView& scene, IntegratorKind kind, uint32_t flags,
                            float prevPdf, vec3 w, vec3 beta) {
  vec3 radiance(0.0f);
  if (scene.backgroundLight >= 0) {
    float weight = EmitterHitWeight(kind, flags, prevPdf, BackgroundLightPdf(scene));
    radiance += beta * scene.background * weight;
  }
  if constexpr (kMap) {
    float lightPdf;
    vec3 le = EnvMapLightLe<kMap>(scene, w, &lightPdf);
    if (!IsBlack(le)) radiance += beta * le * EmitterHitWeight(kind, flags, prevPdf, lightPdf);
  }
  for (uint32_t k = 0; k < scene.distantLightCount; ++k) {
    uint32_t index = scene.distantLights[k];
    const Light& light = scene.lights[index];
    if (!InDirectionalCone(light, w)) continue;
    float lightPdf = InfiniteLightPmf(scene, index) * DirectionalConePdf(light);
    radiance += beta * light.radiance * EmitterHitWeight(kind, flags, prevPdf, lightPdf);
  }
  return radiance;
}

// Where a new ray starts: past the hit point's error bounds (robust), or, for the robustness
// study only, a fixed distance along the normal (--ray-offset EPS).
PT_HDI vec3 SpawnOrigin(const IntegratorParams& params, const SurfaceInteraction& si, vec3 w) {
  if (params.rayOffsetEpsilon <= 0.0f) return OffsetRayOrigin(si.p, si.pError, si.ng, w);
  float side = glm::dot(w, si.ng) < 0.0f ? -1.0f : 1.0f;
  return si.p + (side * params.rayOffsetEpsilon) * si.ng;
}

// First-hit features for denoisers: the surface's reflectance colour, its shading normal on
// the camera's side, and the hit distance (zeros where the camera ray escapes).
PT_HDI void WriteFeatures(PathState ps, uint32_t id, vec3 albedo, vec3 normal, float depth) {
  ps.featureAlbedo[id] = albedo;
  ps.featureNormal[id] = normal;
  ps.featureDepth[id] = depth;
}

// The emission the camera ray's own hit (or escape) gives the path (with feature buffers, at
// depth 0; a camera ray that scatters in a medium first sees none). It carries only the pixel
// footprint's noise, and an emissive texture's detail is in no feature, so the denoiser
// filters the rest and adds this back (docs/denoise.md). Not further along delta bounces: a
// coat's or glass's random choice of lobe makes what they show noisy.
PT_HDI void RecordSeenEmission(PathState ps, uint32_t id, bool camera, vec3 radiance) {
  if (camera) ps.featureEmission[id] = radiance;
}

PT_HDI vec3 FeatureAlbedo(const Material& m) {
  switch (m.type) {
    case MaterialType::kDielectric: return vec3(1.0f);
    case MaterialType::kEmissive: return vec3(0.0f);
    default: return m.albedo;
  }
}

// Shading normals may disagree with the surface: a pair of directions is usable only when the
// geometric surface separates them exactly as the shading frame does (reflection stays on
// one side, transmission crosses), otherwise a ray would leak through the surface. (Curved
// shading folds the BSDF instead of dropping such directions: normal_fold.h.)
PT_HDI bool GeometricallyConsistent(const SurfaceInteraction& si, float woDotNg, vec3 wi,
                                    bool shadingSameSide) {
  bool geometricSameSide = woDotNg * glm::dot(wi, si.ng) > 0.0f;
  return geometricSameSide == shadingSameSide;
}

// Whether EmitterHitWeight reads the light pdf: MIS after a non-delta bounce (a light tree's
// pmf walk is not free, so camera rays that see emitters skip it).
PT_HDI bool HitNeedsLightPdf(IntegratorKind kind, uint32_t flags) {
  return kind == IntegratorKind::kMis && (flags & kFlagSpecular) == 0;
}

// Emission of a surface that also scatters (glTF emissive): MIS-weighted against light
// sampling when the primitive is in the light table, in full when it is not (next-event
// estimation cannot find it then). `from`: the previous vertex (PrevVertexRef).
PT_HDI vec3 SurfaceEmission(const SceneView& scene, const IntegratorParams& params,
                            const SurfaceInteraction& si, const Material& mat, const Ray& ray,
                            uint32_t flags, float prevPdf, const LightRef& from) {
  vec3 le = EmittedRadiance(mat, si.ng, -ray.d);
  if (IsBlack(le) || si.light < 0) return le;
  float lightPdf = HitNeedsLightPdf(params.kind, flags)
                       ? LightPdf(scene, si.light, from, si.p, si.ng) : 0.0f;
  return le * EmitterHitWeight(params.kind, flags, prevPdf, lightPdf);
}

// Ends the path, keeping what it gathered.
PT_HDI void TerminatePath(PathState ps, uint32_t id, uint32_t flags, vec3 radiance) {
  ps.radiance[id] = radiance;
  ps.flags[id] = flags & ~kFlagAlive;
}

// Next-event estimation at a non-delta vertex: sample a light, and queue the shadow ray that
// decides whether its (MIS-weighted) contribution counts.
template <FeatureClass C, uint32_t Q, bool kMap, bool kFlat>
PT_HDI bool QueueLightSample(const SceneView& scene, const IntegratorParams& params,
                             const SurfaceInteraction& si, const HitMaterial<C>& mat,
                             const Frame& frame, vec3 woLocal, float woDotNg, vec3 beta, vec4 u,
                             PathState ps, uint32_t id, uint32_t receiver) {
  LightLiSample ls;
  if (!SampleLightLi<kMap>(scene, ReceiverRef(si.p, receiver), u.x, u.w, vec2(u.y, u.z), &ls) ||
      ls.pdf <= 0.0f)
    return false;
  vec3 wiLocal = frame.ToLocal(ls.wi);
  const bool mis = !ls.isDelta && params.kind == IntegratorKind::kMis;
  const bool flat = kFlat || ShadingNormalIsGeometric(si);
  float foldedPdf = 0.0f;
  vec3 f;
  if (flat) {
    if (!GeometricallyConsistent(si, woDotNg, ls.wi, woLocal.z * wiLocal.z > 0.0f)) return false;
    f = EvalBsdfFor<C, Q>(mat, woLocal, wiLocal) * fabsf(wiLocal.z);
  } else {  // curved shading: the folded BSDF (normal_fold.h), which never leaks light
    f = FoldedEvalCos<C, Q>(mat, si, frame, woLocal, woDotNg, ls.wi, wiLocal,
                            mis ? &foldedPdf : nullptr);
  }
  if (IsBlack(f) || IsBlack(ls.L)) return false;
  float weight = 1.0f;
  if (mis) {
    float bsdfPdf = flat ? PdfBsdfFor<C, Q>(mat, woLocal, wiLocal) : foldedPdf;
    weight = PowerHeuristic(ls.pdf, bsdfPdf);
  }
  vec3 origin = SpawnOrigin(params, si, ls.wi);
  ps.shadowOrigin[id] = origin;
  ps.shadowDir[id] = ls.wi;
  ps.shadowTMax[id] = ls.isInfinite ? kInfinity
                                    : glm::length(ls.pLight - origin) * (1.0f - kShadowEpsilon);
  ps.shadowRadiance[id] = beta * f * ls.L * (weight / ls.pdf);
  return true;
}

// Samples the BSDF for the continuation ray. Returns false when the path ends here.
template <FeatureClass C, uint32_t Q, bool kFlat>
PT_HDI bool ContinuePath(const IntegratorParams& params, const SurfaceInteraction& si,
                         const HitMaterial<C>& mat, const Frame& frame, vec3 wo, vec3 woLocal, vec4 u,
                         uint32_t depth, vec3* beta, uint32_t* flags, PathState ps, uint32_t id) {
  BsdfSample bs;
  if (!SampleBsdfFor<C, Q>(mat, woLocal, u.x, vec2(u.y, u.z), &bs) || bs.pdf <= 0.0f || IsBlack(bs.f))
    return false;
  vec3 wi = frame.FromLocal(bs.wi);
  float pdf = bs.pdf;
  if (kFlat || ShadingNormalIsGeometric(si)) {
    if (!GeometricallyConsistent(si, glm::dot(wo, si.ng), wi, !bs.isTransmission)) return false;
    *beta *= bs.f * (fabsf(bs.wi.z) / bs.pdf);
  } else {  // curved shading: a ray the geometry disputes is mirrored, not lost (normal_fold.h)
    vec3 weight;
    FoldSample<C, Q>(mat, si, frame, woLocal, glm::dot(wo, si.ng), bs, &wi, &weight, &pdf);
    *beta *= weight;
  }
  uint32_t f = (*flags & ~(kFlagSpecular | kDepthMask)) | (depth + 1);
  if (bs.isDelta) f |= kFlagSpecular;
  if (kHasMedia<C> && bs.isTransmission && !bs.passesThrough)
    f = WithMedium(f, glm::dot(wo, si.ng) > 0.0f ? int32_t(si.material) : -1);
  // Russian roulette: survivors carry the weight of those ended.
  if (int(depth) >= params.rrDepth) {
    float q = fmaxf(0.0f, 1.0f - MaxComponent(*beta));
    if (u.w < q) return false;
    *beta /= 1.0f - q;
  }
  *flags = f;
  ps.prevPdf[id] = bs.isDelta ? 0.0f : pdf;
  ps.rayOrigin[id] = SpawnOrigin(params, si, wi);
  ps.rayDir[id] = wi;
  return true;
}

// What the shade stage reads of a path at its vertex.
struct PathVertex {
  uint32_t flags, depth;
  HitRecord hit;
  Ray ray;
  vec3 beta, radiance;
  float prevPdf;
};

// The path's state at its vertex. A camera path (depth 0) has throughput 1 and has gathered
// nothing yet: generate leaves those two arrays alone, and every path's first shading writes
// them (ShadeSurface's end or TerminatePath), so 24 bytes a camera ray are neither written nor
// read.
PT_HDI PathVertex PathVertexOf(PathState ps, uint32_t id, uint32_t flags, bool instanced) {
  const uint32_t depth = DepthOf(flags);
  return PathVertex{flags,
                    depth,
                    LoadHit(ps, id, instanced),
                    Ray{ps.rayOrigin[id], ps.rayDir[id]},
                    depth == 0 ? vec3(1.0f) : ps.throughput[id],
                    depth == 0 ? vec3(0.0f) : ps.radiance[id],
                    ps.prevPdf[id]};
}

// Features describe the first non-specular vertex (NFOR's and Cycles' choice): a mirror or
// smooth glass says little about what the pixel shows, so the features look on through delta
// bounces. While they do, the depth kept is minus the distance so far (the film adds its
// magnitude, should the path end there). Due at the camera ray's hit, and after delta bounces
// only while the features are pending.
PT_HDI bool FeaturesDue(PathState ps, uint32_t id, const PathVertex& v) {
  return v.depth == 0 || ((v.flags & kFlagSpecular) != 0 && ps.featureDepth[id] < 0.0f);
}

template <FeatureClass C, uint32_t Q>
PT_HDI void WriteSurfaceFeatures(PathState ps, uint32_t id, const PathVertex& v,
                                 const HitMaterial<C>& mat, const SurfaceInteraction& si,
                                 vec3 wo) {
  float depth = (v.depth == 0 ? 0.0f : -ps.featureDepth[id]) + v.hit.t;
  bool lookOn = !IsType<Q>(mat, MaterialType::kDiffuse) &&
                !IsType<Q>(mat, MaterialType::kEmissive) && !HasNonDeltaLobeFor<C, Q>(mat);
  // The albedo as seen through the delta bounces (their tint: v.beta).
  WriteFeatures(ps, id, v.beta * FeatureAlbedo(mat), glm::dot(si.ns, wo) < 0.0f ? -si.ns : si.ns,
                lookOn ? -depth : depth);
}

// Escaped: the environment (a constant, a map) and sun disks are lights; a camera ray may see
// a backdrop instead where the environment is hidden from the camera.
template <bool kMap>
PT_HDI void ShadeEscaped(const SceneView& scene, const IntegratorParams& params, PathState ps,
                         uint32_t id, const PathVertex& v) {
  vec3 radiance = v.radiance;
  if (params.featureBuffers && FeaturesDue(ps, id, v))
    WriteFeatures(ps, id, vec3(0.0f), vec3(0.0f), 0.0f);
  if (v.depth == 0 && scene.env.hiddenFromCamera) {
    if (params.Counts(0)) radiance += v.beta * scene.env.cameraColor;
  } else if (params.Counts(v.depth)) {
    radiance += EscapedRadiance<kMap>(scene, params.kind, v.flags, v.prevPdf, v.ray.d, v.beta);
  }
  RecordSeenEmission(ps, id, params.featureBuffers && v.depth == 0, radiance);
  TerminatePath(ps, id, v.flags, radiance);
}

// A surface hit: emission, next-event estimation, the continuation ray.
// kFlat: every shading normal is the geometric one (no vertex normals) and no light tree picks
// the lights, so the curved-shading fold and the tree's receiver code are compiled out.
template <FeatureClass C, uint32_t Q, bool kMap, bool kFlat>
PT_HDI void ShadeSurface(const SceneView& scene, const IntegratorParams& params,
                         const WaveInfo& wave, PathState ps, uint32_t id, PathVertex v) {
  SurfaceInteraction si = MakeInteraction(scene, v.ray, v.hit);
  HitMaterial<C> mat = MaterialAt<C, Q>(scene, scene.prims[v.hit.prim], &si);
  vec3 wo = -v.ray.d;
  if (params.featureBuffers && FeaturesDue(ps, id, v))
    WriteSurfaceFeatures<C, Q>(ps, id, v, mat, si, wo);
  if (IsType<Q>(mat, MaterialType::kEmissive)) {  // emitters reflect nothing
    vec3 le = EmittedRadiance(mat, si.ng, wo);
    if (!IsBlack(le) && si.light >= 0 && params.Counts(v.depth)) {
      LightRef from = kFlat ? ReceiverRef(v.ray.o, kNoReceiver)
                            : PrevVertexRef(scene, ps, id, v.flags, v.ray.o);
      float lightPdf = HitNeedsLightPdf(params.kind, v.flags)
                           ? LightPdf<kMap>(scene, si.light, from, si.p, si.ng) : 0.0f;
      v.radiance += v.beta * le * EmitterHitWeight(params.kind, v.flags, v.prevPdf, lightPdf);
    }
    RecordSeenEmission(ps, id, params.featureBuffers && v.depth == 0, v.radiance);
    TerminatePath(ps, id, v.flags, v.radiance);
    return;
  }
  if constexpr (IsGeneralClass(C)) {
    if (IsType<Q>(mat, MaterialType::kGltfPbr) && params.Counts(v.depth))
      v.radiance += v.beta * SurfaceEmission(scene, params, si, mat, v.ray, v.flags, v.prevPdf,
                                             PrevVertexRef(scene, ps, id, v.flags, v.ray.o));
  }
  RecordSeenEmission(ps, id, params.featureBuffers && v.depth == 0, v.radiance);
  if (int(v.depth) >= params.maxDepth) {
    TerminatePath(ps, id, v.flags, v.radiance);
    return;
  }

  // Smooth and normal-mapped shading: the viewer must see the front of the shading normal.
  if constexpr (!kFlat) si.ns = ViewValidShadingNormal(si, wo);
  Frame frame = Frame::FromZ(si.ns);
  LocalizeMaterial<C>(frame, &mat);
  vec3 woLocal = frame.ToLocal(wo);
  RngKey key = wave.KeyOf(id);
  uint32_t flags = v.flags;
  uint32_t receiver = kFlat ? kNoReceiver : SurfaceReceiver(scene, si, wo, mat);  // light BVH
  if (params.kind != IntegratorKind::kBsdf && params.Counts(v.depth + 1) &&
      HasNonDeltaLobeFor<C, Q>(mat)) {
    vec4 uLight = key.Draw4(v.depth, kDimLight);
    if (QueueLightSample<C, Q, kMap, kFlat>(scene, params, si, mat, frame, woLocal,
                                            glm::dot(wo, si.ng), v.beta, uLight, ps, id,
                                            receiver))
      flags |= kFlagShadow;
  }
  vec4 uBsdf = key.Draw4(v.depth, kDimBsdf);
  bool alive = ContinuePath<C, Q, kFlat>(params, si, mat, frame, wo, woLocal, uBsdf, v.depth,
                                         &v.beta, &flags, ps, id);
  ps.throughput[id] = v.beta;
  ps.radiance[id] = v.radiance;
  ps.flags[id] = alive ? flags : (flags & ~kFlagAlive);
  if (!kFlat && alive && UsesLightTree(scene)) ps.prevNormal[id] = receiver;
}

// Shades path id in the variant of feature class C; Q: the shade queue the kernel serves
// (every path in it escaped, or hit a material of its type), or kAnyQueue; kMap: whether the
// scene has an environment map (its code is compiled out otherwise); kFlat: see ShadeSurface.
template <FeatureClass C, uint32_t Q, bool kMap = true, bool kFlat = false>
PT_HDI void ShadePath(const SceneView& scene, const IntegratorParams& params,
                      const WaveInfo& wave, PathState ps, uint32_t id) {
  uint32_t flags = ps.flags[id];
  if (!IsAlive(flags)) return;
  PathVertex v = PathVertexOf(ps, id, flags, scene.instanceCount != 0);
  // Beer-Lambert attenuation over the segment travelled inside a dielectric.
  int32_t medium = kHasMedia<C> ? MediumOf(flags) : -1;
  if (medium >= 0) {
    vec3 sigma = scene.materials[medium].absorption;
    if (!IsBlack(sigma)) v.beta *= glm::exp(-sigma * v.hit.t);
  }
  // A queue's kernel knows at compile time whether its paths escaped.
  bool escaped = Q == kAnyQueue ? v.hit.prim == HitRecord::kNoHit : Q == kEscapedQueue;
  if (escaped) {
    ShadeEscaped<kMap>(scene, params, ps, id, v);
    return;
  }
  if constexpr (Q != kEscapedQueue)
    ShadeSurface<C, Q, kMap, kFlat>(scene, params, wave, ps, id, v);
}

}  // namespace pt
