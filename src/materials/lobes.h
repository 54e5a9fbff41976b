// The basic lobes, in the local shading frame (z = shading normal; for dielectrics z points
// outside): Lambert, smooth and GGX conductor, smooth and GGX dielectric. bsdf.h dispatches
// over the materials built from them (plastic.h and gltf_pbr.h add layered ones); the GGX
// distribution is in microfacet.h.
//
// Conventions (pbrt-v4): wo and wi point away from the surface; f excludes the cosine; pdf is
// per unit solid angle for non-delta lobes. For a delta lobe pdf is the discrete probability of
// choosing it and f is chosen so that f * |cos wi| / pdf is the path weight.
// Transport mode is always radiance (camera paths), so refraction scales by 1 / eta^2.
#pragma once

#include "src/core/sampling.h"
#include "src/materials/fresnel.h"
#include "src/materials/microfacet.h"
#include "src/scene/scene_types.h"

namespace pt {

// GGX alpha = roughness^2 below kSmoothAlpha: the lobe is a perfect mirror / smooth glass.
PT_HDI bool IsSmooth(const Material& m) { return IsEffectivelySmooth(m.roughness); }
// Smooth glass, or glass that does not bend light (ior 1: no half vector for refraction).
PT_HDI bool IsSmoothDielectric(const Material& m) { return IsSmooth(m) || m.ior == 1.0f; }

// ---- Lambertian (two-sided: wo.z < 0 samples and evaluates the lower hemisphere) ----

PT_HDI vec3 EvalLambert(const Material& m, vec3 wo, vec3 wi) {
  return SameHemisphere(wo, wi) ? m.albedo * kInvPi : vec3(0.0f);
}

PT_HDI float PdfLambert(vec3 wo, vec3 wi) {
  return SameHemisphere(wo, wi) ? AbsCosTheta(wi) * kInvPi : 0.0f;
}

PT_HDI bool SampleLambert(const Material& m, vec3 wo, vec2 u, BsdfSample* s) {
  if (wo.z == 0.0f || IsBlack(m.albedo)) return false;
  vec3 wi = SampleCosineHemisphere(u);
  if (wo.z < 0.0f) wi.z = -wi.z;  // mirror: the back face behaves as the front
  float pdf = PdfLambert(wo, wi);
  if (pdf == 0.0f) return false;  // grazing sample: no contribution, avoid 0/0 weights
  s->f = m.albedo * kInvPi;
  s->wi = wi;
  s->pdf = pdf;
  s->isDelta = false;
  s->isTransmission = false;
  s->eta = 1.0f;
  return true;
}

// ---- Smooth conductor: perfect mirror with Schlick Fresnel, F0 = albedo (two-sided) ----

PT_HDI bool SampleSmoothConductor(const Material& m, vec3 wo, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  vec3 wi = vec3(-wo.x, -wo.y, wo.z);  // reflection about z, on wo's side either way
  float cosI = AbsCosTheta(wi);
  s->f = FresnelSchlick(m.albedo, cosI) / cosI;
  s->wi = wi;
  s->pdf = 1.0f;
  s->isDelta = true;
  s->isTransmission = false;
  s->eta = 1.0f;
  return !IsBlack(s->f);
}

// ---- Rough conductor: GGX reflection, Schlick Fresnel at the microfacet (two-sided) ----

PT_HDI vec3 EvalRoughConductor(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z < 0.0f) {
    wo = FlipZ(wo);
    wi = FlipZ(wi);
  }
  vec3 wm;
  if (wo.z <= 0.0f || wi.z <= 0.0f || !ReflectionHalfVector(wo, wi, &wm)) return vec3(0.0f);
  GgxDistribution d{GgxAlpha(m.roughness)};
  float dg = d.D(wm) * d.G(wo, wi) / (4.0f * wo.z * wi.z);
  return FresnelSchlick(m.albedo, glm::dot(wo, wm)) * dg;
}

PT_HDI float PdfRoughConductor(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z < 0.0f) {
    wo = FlipZ(wo);
    wi = FlipZ(wi);
  }
  vec3 wm;
  if (wo.z <= 0.0f || wi.z <= 0.0f || !ReflectionHalfVector(wo, wi, &wm)) return 0.0f;
  return GgxDistribution{GgxAlpha(m.roughness)}.ReflectionPdf(wo, wm);
}

// Reflects wo about a visible normal; the weight is F G / G1(wo) <= 1.
PT_HDI bool SampleRoughConductor(const Material& m, vec3 wo, vec2 u, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  bool back = wo.z < 0.0f;
  if (back) wo = FlipZ(wo);
  GgxDistribution d{GgxAlpha(m.roughness)};
  vec3 wm = d.SampleVisibleNormal(wo, u);
  vec3 wi = Reflect(wo, wm);
  if (wi.z <= 0.0f) return false;  // shadowed: single scattering loses this energy
  float pdf = d.ReflectionPdf(wo, wm);
  if (pdf == 0.0f) return false;
  float dg = d.D(wm) * d.G(wo, wi) / (4.0f * wo.z * wi.z);
  s->f = FresnelSchlick(m.albedo, glm::dot(wo, wm)) * dg;
  s->wi = back ? FlipZ(wi) : wi;
  s->pdf = pdf;
  s->isDelta = false;
  s->isTransmission = false;
  s->eta = 1.0f;
  return true;
}

// ---- Smooth dielectric: Fresnel-weighted choice of reflection or refraction ----
// wo.z > 0 is outside (vacuum), wo.z < 0 inside the medium of index m.ior.

PT_HDI bool SampleSmoothDielectric(const Material& m, vec3 wo, float uc, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  float r = FresnelDielectric(wo.z, m.ior);  // 1 under total internal reflection
  float t = 1.0f - r;
  if (uc < r || t <= 0.0f) {
    vec3 wi = vec3(-wo.x, -wo.y, wo.z);
    s->f = vec3(r / AbsCosTheta(wi));
    s->wi = wi;
    s->pdf = r;
    s->isDelta = true;
    s->isTransmission = false;
    s->eta = 1.0f;
    return true;
  }
  vec3 wi;
  float etap;
  if (!Refract(wo, vec3(0.0f, 0.0f, 1.0f), m.ior, &etap, &wi)) return false;
  float cosI = AbsCosTheta(wi);
  if (cosI == 0.0f) return false;
  // Radiance is compressed by eta^2 on entering a denser medium, so that a clear sphere in a
  // uniform environment is invisible.
  s->f = vec3(t / (cosI * etap * etap));
  s->wi = wi;
  s->pdf = t;
  s->isDelta = true;
  s->isTransmission = true;
  s->eta = etap;
  return true;
}

// ---- Rough dielectric: GGX reflection and transmission with exact Fresnel (pbrt-v4) ----
// wo.z > 0 is outside. Reflection or refraction is chosen with the Fresnel reflectance of the
// sampled microfacet, so every sample weighs G / G1(wo) (times 1 / eta^2 when refracting).

// What Eval and Pdf need about a pair: pbrt-v4's generalised half vector, facing +z.
struct DielectricPair {
  vec3 wm;
  float etap;  // relative index crossed; 1 for reflection
  bool reflect;
};

PT_HDI bool MakeDielectricPair(float ior, vec3 wo, vec3 wi, DielectricPair* q) {
  float cosO = wo.z, cosI = wi.z;
  if (cosO == 0.0f || cosI == 0.0f) return false;
  q->reflect = cosO * cosI > 0.0f;
  q->etap = q->reflect ? 1.0f : (cosO > 0.0f ? ior : 1.0f / ior);
  vec3 h = wi * q->etap + wo;
  float lenSq = glm::dot(h, h);
  if (lenSq == 0.0f) return false;
  h /= sqrtf(lenSq);
  if (h.z < 0.0f) h = -h;
  // A microfacet that either direction sees from behind contributes nothing.
  if (glm::dot(h, wi) * cosI < 0.0f || glm::dot(h, wo) * cosO < 0.0f) return false;
  q->wm = h;
  return true;
}

// f for a pair, given the microfacet's Fresnel reflectance r.
PT_HDI float RoughDielectricF(const GgxDistribution& d, float r, vec3 wo, vec3 wi,
                              const DielectricPair& q) {
  float dg = d.D(q.wm) * d.G(wo, wi);
  if (q.reflect) return dg * r / fabsf(4.0f * wi.z * wo.z);
  float cosIM = glm::dot(wi, q.wm), cosOM = glm::dot(wo, q.wm);
  float denom = Sqr(cosIM + cosOM / q.etap) * wi.z * wo.z;
  if (denom == 0.0f) return 0.0f;
  // Radiance is compressed by etap^2 on entering the denser medium (as the smooth lobe).
  return dg * (1.0f - r) * fabsf(cosIM * cosOM / denom) / Sqr(q.etap);
}

// Density of the pair: VNDF, times the Jacobian of reflection or refraction, times the
// probability r or 1 - r of the branch.
PT_HDI float RoughDielectricPdf(const GgxDistribution& d, float r, vec3 wo, vec3 wi,
                                const DielectricPair& q) {
  if (q.reflect) return d.ReflectionPdf(wo, q.wm) * r;
  float cosIM = glm::dot(wi, q.wm);
  float denom = Sqr(cosIM + glm::dot(wo, q.wm) / q.etap);
  if (denom == 0.0f) return 0.0f;
  return d.VisibleD(wo, q.wm) * (fabsf(cosIM) / denom) * (1.0f - r);  // dwm / dwi
}

PT_HDI vec3 EvalRoughDielectric(const Material& m, vec3 wo, vec3 wi) {
  DielectricPair q;
  if (!MakeDielectricPair(m.ior, wo, wi, &q)) return vec3(0.0f);
  float r = FresnelDielectric(glm::dot(wo, q.wm), m.ior);
  return vec3(RoughDielectricF(GgxDistribution{GgxAlpha(m.roughness)}, r, wo, wi, q));
}

PT_HDI float PdfRoughDielectric(const Material& m, vec3 wo, vec3 wi) {
  DielectricPair q;
  if (!MakeDielectricPair(m.ior, wo, wi, &q)) return 0.0f;
  float r = FresnelDielectric(glm::dot(wo, q.wm), m.ior);
  return RoughDielectricPdf(GgxDistribution{GgxAlpha(m.roughness)}, r, wo, wi, q);
}

PT_HDI bool SampleRoughDielectric(const Material& m, vec3 wo, float uc, vec2 u,
                                  BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  GgxDistribution d{GgxAlpha(m.roughness)};
  DielectricPair q{d.SampleVisibleNormal(wo, u), 1.0f, true};
  float r = FresnelDielectric(glm::dot(wo, q.wm), m.ior);  // 1 under total internal reflection
  vec3 wi;
  if (uc < r) {
    wi = Reflect(wo, q.wm);
    if (!SameHemisphere(wo, wi)) return false;
  } else {
    if (!Refract(wo, q.wm, m.ior, &q.etap, &wi) || wi.z * wo.z >= 0.0f) return false;
    q.reflect = false;
  }
  s->pdf = RoughDielectricPdf(d, r, wo, wi, q);
  if (s->pdf == 0.0f) return false;
  s->f = vec3(RoughDielectricF(d, r, wo, wi, q));
  s->wi = wi;
  s->isDelta = false;
  s->isTransmission = !q.reflect;
  s->eta = q.etap;
  return true;
}

}  // namespace pt
