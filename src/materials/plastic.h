// Plastic: a dielectric coat of index m.ior over a diffuse base of m.albedo, as Mitsuba 3's
// `plastic` (smooth coat: a delta reflection) and `roughplastic` (GGX coat, alpha =
// roughness^2) with nonlinear = false. Two-sided (shared/scene-format.md): wo.z < 0 is
// mirrored to the front.
//
// Base (both variants, Mitsuba's linear weighting): light crosses the coat with the smooth
// transmittance 1 - F(cos) on the way in and out, scatters off the Lambertian base, and the
// internal reflections are summed as 1 / (1 - fdr_int):
//   f_base = albedo / (1 - fdr_int) / eta^2 (1 - F(cos_o)) (1 - F(cos_i)) / pi,
// whose directional albedo is exactly albedo (1 - F(cos_o)), because fdr_int comes from
// fdr_ext by reciprocity (FresnelDiffuseReflectance). Coat: a GGX reflection with the exact
// Fresnel F(wo.wm). Sampling picks the coat with Mitsuba's probability F w / (F w + (1 - F)(1
// - w)), w = m_specular_sampling_weight = 1 / (1 + mean(albedo)); Eval and Pdf of the rough
// variant are the mixture, the smooth variant's coat is a delta lobe outside Eval and Pdf.
//
// One deliberate difference: Mitsuba's roughplastic weights the base by a table of the rough
// coat's transmittance precomputed per material; Material has no room for it, so the rough
// coat uses the smooth 1 - F too. The total albedo is then E_coat(mu) + albedo (1 - F(mu)),
// where E_coat exceeds F by at most ~7e-4 (mid angles, roughness 0.2-0.3): only an albedo
// within 1e-3 of 1 can reflect more than it receives, and by less than 1e-3.
#pragma once

#include "src/core/sampling.h"
#include "src/materials/fresnel.h"
#include "src/materials/microfacet.h"
#include "src/scene/scene_types.h"

namespace pt {

// Mitsuba's per-material constants, recomputed per call (a few flops; Material stays small).
struct PlasticLayer {
  float eta;             // coat index, outside is vacuum
  float specularWeight;  // m_specular_sampling_weight with specular_reflectance 1
  vec3 baseScale;        // albedo / (1 - fdr_int) / eta^2
  GgxDistribution coat;
  bool smoothCoat;
};

PT_HDI PlasticLayer MakePlasticLayer(const Material& m) {
  PlasticLayer p;
  p.eta = m.ior;
  float meanAlbedo = (m.albedo.x + m.albedo.y + m.albedo.z) / 3.0f;
  p.specularWeight = 1.0f / (meanAlbedo + 1.0f);
  float fdrInt = FresnelDiffuseReflectance(1.0f / m.ior);
  p.baseScale = m.albedo / ((1.0f - fdrInt) * m.ior * m.ior);
  p.coat.alpha = GgxAlpha(m.roughness);
  p.smoothCoat = IsEffectivelySmooth(m.roughness);
  return p;
}

// Probability of sampling the coat for wo at cosO > 0 (Mitsuba's prob_specular).
PT_HDI float PlasticCoatProbability(const PlasticLayer& p, float cosO) {
  float f = FresnelDielectric(cosO, p.eta);
  float coat = f * p.specularWeight, base = (1.0f - f) * (1.0f - p.specularWeight);
  return coat + base > 0.0f ? coat / (coat + base) : 0.0f;
}

// The diffuse base; wo and wi on the front side.
PT_HDI vec3 EvalPlasticBase(const PlasticLayer& p, vec3 wo, vec3 wi) {
  float to = 1.0f - FresnelDielectric(wo.z, p.eta), ti = 1.0f - FresnelDielectric(wi.z, p.eta);
  return p.baseScale * (to * ti * kInvPi);
}

// The rough coat's GGX reflection; wo and wi on the front side.
PT_HDI float EvalPlasticCoat(const PlasticLayer& p, vec3 wo, vec3 wi) {
  vec3 wm;
  if (!ReflectionHalfVector(wo, wi, &wm)) return 0.0f;
  float f = FresnelDielectric(glm::dot(wo, wm), p.eta);
  return p.coat.D(wm) * p.coat.G(wo, wi) * f / (4.0f * wo.z * wi.z);
}

PT_HDI float PdfPlasticCoat(const PlasticLayer& p, vec3 wo, vec3 wi) {
  vec3 wm;
  if (!ReflectionHalfVector(wo, wi, &wm)) return 0.0f;
  return p.coat.ReflectionPdf(wo, wm);
}

// f without the cosine on the front side: the base, plus the coat when it is rough.
PT_HDI vec3 EvalPlasticFront(const PlasticLayer& p, vec3 wo, vec3 wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return vec3(0.0f);
  vec3 f = EvalPlasticBase(p, wo, wi);
  if (!p.smoothCoat) f += vec3(EvalPlasticCoat(p, wo, wi));
  return f;
}

// The mixture density with which SamplePlastic draws non-delta directions (front side).
PT_HDI float PdfPlasticFront(const PlasticLayer& p, vec3 wo, vec3 wi) {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  float pCoat = PlasticCoatProbability(p, wo.z);
  float pdf = (1.0f - pCoat) * CosineHemispherePdf(wi.z);
  if (!p.smoothCoat) pdf += pCoat * PdfPlasticCoat(p, wo, wi);
  return pdf;
}

PT_HDI vec3 EvalPlastic(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z < 0.0f) return EvalPlasticFront(MakePlasticLayer(m), FlipZ(wo), FlipZ(wi));
  return EvalPlasticFront(MakePlasticLayer(m), wo, wi);
}

PT_HDI float PdfPlastic(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z < 0.0f) return PdfPlasticFront(MakePlasticLayer(m), FlipZ(wo), FlipZ(wi));
  return PdfPlasticFront(MakePlasticLayer(m), wo, wi);
}

// uc picks coat or base, u the direction.
PT_HDI bool SamplePlastic(const Material& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  bool back = wo.z < 0.0f;
  if (back) wo = FlipZ(wo);
  PlasticLayer p = MakePlasticLayer(m);
  float pCoat = PlasticCoatProbability(p, wo.z);
  bool coat = uc < pCoat;
  if (coat && p.smoothCoat) {
    s->wi = vec3(-wo.x, -wo.y, wo.z);
    s->f = vec3(FresnelDielectric(wo.z, p.eta) / wo.z);
    s->pdf = pCoat;
    s->isDelta = true;
  } else {
    vec3 wi = coat ? Reflect(wo, p.coat.SampleVisibleNormal(wo, u)) : SampleCosineHemisphere(u);
    if (wi.z <= 0.0f) return false;  // the coat sent it below the horizon: absorbed
    s->wi = wi;
    s->f = EvalPlasticFront(p, wo, wi);
    s->pdf = PdfPlasticFront(p, wo, wi);
    s->isDelta = false;
    if (s->pdf == 0.0f) return false;
  }
  if (back) s->wi = FlipZ(s->wi);
  s->isTransmission = false;
  s->eta = 1.0f;
  return true;
}

}  // namespace pt
