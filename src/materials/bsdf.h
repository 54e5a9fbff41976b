// BSDF evaluation, pdf and importance sampling for the closed set of materials, in the local
// shading frame (z = shading normal; for dielectrics z points outside). One switch on
// MaterialType per entry point; each lobe is a small function so GGX lobes (rough conductor,
// rough dielectric, plastic) slot in beside the smooth ones without touching the callers.
//
// Conventions (pbrt-v4): wo and wi point away from the surface; f excludes the cosine; pdf is
// per unit solid angle for non-delta lobes. For a delta lobe pdf is the discrete probability of
// choosing it and f is chosen so that f * |cos wi| / pdf is the path weight.
// Transport mode is always radiance (camera paths), so refraction scales by 1 / eta^2.
#pragma once

#include "src/core/sampling.h"
#include "src/materials/fresnel.h"
#include "src/scene/scene_types.h"

namespace pt {

struct BsdfSample {
  vec3 f = vec3(0.0f);
  vec3 wi = vec3(0.0f);
  float pdf = 0.0f;
  bool isDelta = false;
  bool isTransmission = false;
  float eta = 1.0f;  // relative index crossed (pbrt's etap): 1 for reflection
};

PT_HDI float AbsCosTheta(vec3 w) { return fabsf(w.z); }
PT_HDI bool SameHemisphere(vec3 a, vec3 b) { return a.z * b.z > 0.0f; }

// GGX alpha = roughness^2 (glTF). Below this a lobe is a perfect mirror (pbrt-v4's
// EffectivelySmooth). The rough lobes are not implemented yet and the loader rejects
// roughness > 0, so for now every conductor and dielectric uses its smooth lobe.
constexpr float kSmoothAlpha = 1e-3f;
PT_HDI bool IsSmooth(const Material& m) { return m.roughness * m.roughness < kSmoothAlpha; }

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

// ---- Entry points ----

// f(wo, wi) without the cosine. Zero for delta lobes and for materials that reflect nothing.
PT_HDI vec3 EvalBsdf(const Material& m, vec3 wo, vec3 wi) {
  switch (m.type) {
    case MaterialType::kDiffuse: return EvalLambert(m, wo, wi);
    case MaterialType::kConductor:   // smooth: delta (GGX lobe goes here when !IsSmooth)
    case MaterialType::kDielectric:  // smooth: delta (rough GGX goes here)
    case MaterialType::kPlastic:     // not rendered yet: the loader rejects it
    case MaterialType::kEmissive:    // emits, reflects nothing
    default: return vec3(0.0f);
  }
}

// Solid-angle density with which SampleBsdf produces wi. Zero for delta lobes.
PT_HDI float PdfBsdf(const Material& m, vec3 wo, vec3 wi) {
  switch (m.type) {
    case MaterialType::kDiffuse: return PdfLambert(wo, wi);
    case MaterialType::kConductor:
    case MaterialType::kDielectric:
    case MaterialType::kPlastic:
    case MaterialType::kEmissive:
    default: return 0.0f;
  }
}

// Draws wi given wo; uc picks a lobe, u the direction. Returns false when the path ends here
// (absorbed, black, grazing, or a material that reflects nothing: emissive, and plastic until
// the rough-materials issue lands; the loader rejects plastic until then).
PT_HDI bool SampleBsdf(const Material& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  switch (m.type) {
    case MaterialType::kDiffuse: return SampleLambert(m, wo, u, s);
    case MaterialType::kConductor: return SampleSmoothConductor(m, wo, s);
    case MaterialType::kDielectric: return SampleSmoothDielectric(m, wo, uc, s);
    case MaterialType::kPlastic:
    case MaterialType::kEmissive:
    default: return false;
  }
}

// True where next-event estimation can contribute (some lobe is not a Dirac delta). Becomes
// !IsSmooth(m) for conductors and dielectrics, and true for plastic, with the GGX lobes.
PT_HDI bool HasNonDeltaLobe(const Material& m) {
  switch (m.type) {
    case MaterialType::kDiffuse: return !IsBlack(m.albedo);
    case MaterialType::kConductor:
    case MaterialType::kDielectric:
    case MaterialType::kPlastic:
    case MaterialType::kEmissive:
    default: return false;
  }
}

}  // namespace pt
