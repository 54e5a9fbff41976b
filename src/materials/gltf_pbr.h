// The glTF 2.0 metallic-roughness material (specification, appendix B), with
// KHR_materials_transmission, _volume and _ior, as one BSDF in the local shading frame:
//
//   f = m metal + (1 - m) [(1 - t) coated diffuse + t transmission]
//
//   metal           GGX reflection, Schlick Fresnel with F0 = baseColor (exactly lobes.h's
//                   rough conductor; a mirror below kSmoothAlpha).
//   coated diffuse  GGX reflection with Schlick F0 = ((ior - 1) / (ior + 1))^2 over a diffuse
//                   base of baseColor. The specification weights the base by 1 - F(v.h), which
//                   creates energy at grazing angles; here the base is scaled by the albedo the
//                   coat leaves, f_base = c / pi (1 - E(mu_o)) (1 - E(mu_i)) / (1 - E_avg)
//                   (Kelemen and Szirmay-Kalos 2001; Kulla and Conty 2017), which is
//                   reciprocal and whose albedo is exactly c (1 - E(mu_o)), so the total never
//                   exceeds 1. E is the coat's albedo from ggx_albedo_table.h (upper bounds,
//                   so the base only ever loses energy), exact for a smooth coat.
//   transmission    volume (thickness > 0): lobes.h's dielectric (exact Fresnel, refraction,
//                   total internal reflection inside, 1 / eta^2 radiance scaling), the
//                   transmitted part tinted by sqrt(baseColor) per crossing, so light through
//                   a closed object is tinted by baseColor once; Beer-Lambert absorption from
//                   the material's absorption, as the dielectric. Thin-walled (no volume):
//                   the shell reflects with the dielectric's Fresnel and transmits the rest
//                   unbent (the reflection mirrored through the surface; rough walls blur it
//                   with the same GGX lobe), tinted by baseColor. Exact Fresnel rather than
//                   Schlick: Schlick has no total internal reflection for light leaving glass.
//
// Why one new type and not the existing ones: plastic's coat (Mitsuba's) has another Fresnel
// and base weighting than glTF's, conductor covers only m = 1 without textures, and the
// dielectric has no tint; one closed type keeps the mixtures of textured m and t exact.
// The opaque lobes are two-sided (the back mirrors the front; glTF's doubleSided culling is
// done by the intersector); thin walls are symmetric; a volume's inside is wo.z < 0.
//
// Sampling picks the specular, diffuse or transmission lobe with probability proportional to
// an estimate of its albedo for wo (Schlick at mu_o, the diffuse albedo, the transmission
// weight); the GGX lobes use visible-normal sampling. Eval and Pdf are the sums over the
// non-delta lobes, so a sample's f and pdf are those of its direction (as plastic.h).
#pragma once

#include "src/materials/ggx_albedo_table.h"
#include "src/materials/lobes.h"

namespace pt {

// ---- The coat's albedo (Schlick F0 over GGX): E(mu) and its hemispherical average ----

PT_HDI float SchlickWeight(float cosTheta) {
  float m = Clamp01(1.0f - fabsf(cosTheta));
  return (m * m) * (m * m) * m;
}

struct CoatAlbedo {
  float f0, roughness;
  bool smooth;

  // Directional albedo for a view at cosine mu (an upper bound when rough).
  PT_HDI float At(float mu) const {
    if (smooth) return f0 + (1.0f - f0) * SchlickWeight(mu);
    float x = sqrtf(Clamp01(mu)) * float(kGgxAlbedoMu - 1);
    float y = Clamp01(roughness) * float(kGgxAlbedoRoughness - 1);
    int i = int(fminf(x, float(kGgxAlbedoMu - 2))), j = int(fminf(y, float(kGgxAlbedoRoughness - 2)));
    // Linear in mu between nodes mu_i = (i / 31)^2 (the table's average assumes it).
    float mu0 = Sqr(float(i) / float(kGgxAlbedoMu - 1)), mu1 = Sqr(float(i + 1) / float(kGgxAlbedoMu - 1));
    float fx = Clamp01((Clamp01(mu) - mu0) / (mu1 - mu0)), fy = y - float(j);
    auto lerp2 = [&](int base) {
      int a = base + j * kGgxAlbedoMu + i, b = a + kGgxAlbedoMu;
      float lo = (1.0f - fx) * GgxAlbedoEntry(a) + fx * GgxAlbedoEntry(a + 1);
      float hi = (1.0f - fx) * GgxAlbedoEntry(b) + fx * GgxAlbedoEntry(b + 1);
      return (1.0f - fy) * lo + fy * hi;
    };
    return f0 * lerp2(kGgxAlbedoE1) + (1.0f - f0) * lerp2(kGgxAlbedoE5);
  }

  // 2 * integral of At(mu) mu over [0, 1], exactly for the interpolated table.
  PT_HDI float Average() const {
    if (smooth) return f0 + (1.0f - f0) / 21.0f;  // 2 * integral of (1 - mu)^5 mu = 1 / 21
    float y = Clamp01(roughness) * float(kGgxAlbedoRoughness - 1);
    int j = int(fminf(y, float(kGgxAlbedoRoughness - 2)));
    float fy = y - float(j);
    auto row = [&](int base) {
      return (1.0f - fy) * GgxAlbedoEntry(base + j) + fy * GgxAlbedoEntry(base + j + 1);
    };
    return f0 * row(kGgxAlbedoAvg1) + (1.0f - f0) * row(kGgxAlbedoAvg5);
  }
};

// ---- The material's constants at a point ----

struct GltfPbr {
  vec3 base;              // baseColor
  float metallic;
  float coatWeight;       // (1 - m)(1 - t)
  float transWeight;      // (1 - m) t
  float f0;               // dielectric F0 from ior
  GgxDistribution ggx;
  bool smooth;            // GGX lobes are mirrors (alpha < kSmoothAlpha)
  bool thin;              // thin-walled transmission
  Material glass;         // lobes.h's dielectric with the material's ior and roughness
  CoatAlbedo coat;
  float baseNorm;         // 1 / (pi (1 - E_avg)), 0 when the coat reflects everything
};

PT_HDI GltfPbr MakeGltfPbr(const Material& m) {
  GltfPbr p;
  p.base = m.albedo;
  p.metallic = Clamp01(m.metallic);
  float t = Clamp01(m.transmission);
  p.coatWeight = (1.0f - p.metallic) * (1.0f - t);
  p.transWeight = (1.0f - p.metallic) * t;
  p.f0 = Sqr((m.ior - 1.0f) / (m.ior + 1.0f));
  p.ggx.alpha = GgxAlpha(m.roughness);
  p.smooth = IsEffectivelySmooth(m.roughness);
  p.thin = (m.flags & kMaterialThinWalled) != 0;
  p.glass.type = MaterialType::kDielectric;
  p.glass.ior = m.ior;
  p.glass.roughness = m.roughness;
  p.coat = CoatAlbedo{p.f0, m.roughness, p.smooth};
  float avg = p.coat.Average();
  p.baseNorm = avg < 1.0f ? kInvPi / (1.0f - avg) : 0.0f;
  return p;
}

// Tint of light crossing the surface: baseColor through a thin wall, its square root per
// crossing of a volume's boundary.
PT_HDI vec3 TransmissionTint(const GltfPbr& p) { return p.thin ? p.base : glm::sqrt(p.base); }

// Fresnel of the GGX reflection lobe (metal and coat together) at cosine c: Schlick with the
// mixed F0, weighted by each part's share.
PT_HDI vec3 GltfSpecularFresnel(const GltfPbr& p, float c) {
  float s = SchlickWeight(c);
  vec3 metal = p.base + (vec3(1.0f) - p.base) * s;
  return p.metallic * metal + vec3(p.coatWeight * (p.f0 + (1.0f - p.f0) * s));
}

// ---- Thin-walled transmission: the GGX lobe mirrored through the surface ----

// Reflection and transmission of a thin wall, wo.z > 0; wi on either side.
PT_HDI float EvalThinWall(const GltfPbr& p, vec3 wo, vec3 wi, bool* transmits) {
  *transmits = wi.z < 0.0f;
  vec3 wr = *transmits ? FlipZ(wi) : wi, wm;
  if (wr.z <= 0.0f || !ReflectionHalfVector(wo, wr, &wm)) return 0.0f;
  float r = FresnelDielectric(glm::dot(wo, wm), p.glass.ior);
  float dg = p.ggx.D(wm) * p.ggx.G(wo, wr) / (4.0f * wo.z * wr.z);
  return dg * (*transmits ? 1.0f - r : r);
}

PT_HDI float PdfThinWall(const GltfPbr& p, vec3 wo, vec3 wi) {
  vec3 wr = wi.z < 0.0f ? FlipZ(wi) : wi, wm;
  if (wr.z <= 0.0f || !ReflectionHalfVector(wo, wr, &wm)) return 0.0f;
  float r = FresnelDielectric(glm::dot(wo, wm), p.glass.ior);
  return p.ggx.ReflectionPdf(wo, wm) * (wi.z < 0.0f ? 1.0f - r : r);
}

// ---- Lobe choice ----

struct GltfLobeChoice {
  float spec, diffuse, trans;  // probabilities, summing to 1 (all 0: nothing to sample)
};

PT_HDI GltfLobeChoice ChooseGltfLobes(const GltfPbr& p, float mu) {
  float spec = Luminance(GltfSpecularFresnel(p, mu));
  float diffuse = p.coatWeight * Luminance(p.base) * (1.0f - p.coat.At(mu));
  if (!(p.baseNorm > 0.0f)) diffuse = 0.0f;
  float trans = 0.0f;
  if (p.transWeight > 0.0f) {
    float r = FresnelDielectric(mu, p.glass.ior);
    trans = p.transWeight * (r + (1.0f - r) * fmaxf(Luminance(TransmissionTint(p)), 0.05f));
  }
  float sum = spec + diffuse + trans;
  if (!(sum > 0.0f)) return GltfLobeChoice{0.0f, 0.0f, 0.0f};
  return GltfLobeChoice{spec / sum, diffuse / sum, trans / sum};
}

// ---- Eval and Pdf of the non-delta lobes ----

// Whether the transmission part has no density (smooth glass, or a volume that does not bend
// light): it is then sampled as delta lobes only.
PT_HDI bool GltfTransmissionIsDelta(const GltfPbr& p) {
  return p.thin ? p.smooth : IsSmoothDielectric(p.glass);
}

// The opaque lobes for wo, wi on the front side (wo.z > 0, wi.z > 0).
PT_HDI vec3 EvalGltfOpaque(const GltfPbr& p, vec3 wo, vec3 wi) {
  vec3 f(0.0f);
  if (p.coatWeight > 0.0f && p.baseNorm > 0.0f) {
    float scale = (1.0f - p.coat.At(wo.z)) * (1.0f - p.coat.At(wi.z)) * p.baseNorm;
    f = p.base * (p.coatWeight * scale);
  }
  vec3 wm;
  if (!p.smooth && ReflectionHalfVector(wo, wi, &wm)) {
    float dg = p.ggx.D(wm) * p.ggx.G(wo, wi) / (4.0f * wo.z * wi.z);
    f += GltfSpecularFresnel(p, glm::dot(wo, wm)) * dg;
  }
  return f;
}

// The transmission part (its reflection included) for any wo, wi; weighted by transWeight.
PT_HDI vec3 EvalGltfTransmission(const GltfPbr& p, vec3 wo, vec3 wi) {
  if (p.transWeight <= 0.0f || GltfTransmissionIsDelta(p)) return vec3(0.0f);
  if (p.thin) {
    bool transmits;
    float flip = wo.z < 0.0f ? -1.0f : 1.0f;
    float f = EvalThinWall(p, wo * vec3(1, 1, flip), wi * vec3(1, 1, flip), &transmits);
    return p.transWeight * f * (transmits ? p.base : vec3(1.0f));
  }
  vec3 f = EvalRoughDielectric(p.glass, wo, wi);
  return p.transWeight * f * (wo.z * wi.z < 0.0f ? TransmissionTint(p) : vec3(1.0f));
}

PT_HDI float PdfGltfTransmission(const GltfPbr& p, vec3 wo, vec3 wi) {
  if (p.transWeight <= 0.0f || GltfTransmissionIsDelta(p)) return 0.0f;
  if (!p.thin) return PdfRoughDielectric(p.glass, wo, wi);
  float flip = wo.z < 0.0f ? -1.0f : 1.0f;
  return PdfThinWall(p, wo * vec3(1, 1, flip), wi * vec3(1, 1, flip));
}

PT_HDI vec3 EvalGltfPbrLobes(const GltfPbr& p, vec3 wo, vec3 wi) {
  vec3 f = EvalGltfTransmission(p, wo, wi);
  if (wo.z < 0.0f) wo = FlipZ(wo), wi = FlipZ(wi);  // the opaque lobes are two-sided
  if (wo.z > 0.0f && wi.z > 0.0f) f += EvalGltfOpaque(p, wo, wi);
  return f;
}

PT_HDI float PdfGltfPbrLobes(const GltfPbr& p, const GltfLobeChoice& c, vec3 wo, vec3 wi) {
  float pdf = c.trans > 0.0f ? c.trans * PdfGltfTransmission(p, wo, wi) : 0.0f;
  if (wo.z < 0.0f) wo = FlipZ(wo), wi = FlipZ(wi);
  if (wo.z > 0.0f && wi.z > 0.0f) {
    pdf += c.diffuse * CosineHemispherePdf(wi.z);
    vec3 wm;
    if (!p.smooth && c.spec > 0.0f && ReflectionHalfVector(wo, wi, &wm))
      pdf += c.spec * p.ggx.ReflectionPdf(wo, wm);
  }
  return pdf;
}

PT_HDI vec3 EvalGltfPbr(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z == 0.0f) return vec3(0.0f);
  return EvalGltfPbrLobes(MakeGltfPbr(m), wo, wi);
}

PT_HDI float PdfGltfPbr(const Material& m, vec3 wo, vec3 wi) {
  if (wo.z == 0.0f) return 0.0f;
  GltfPbr p = MakeGltfPbr(m);
  return PdfGltfPbrLobes(p, ChooseGltfLobes(p, fabsf(wo.z)), wo, wi);
}

// ---- Sampling ----

// A non-delta direction's record: f and pdf of the whole mixture there.
PT_HDI bool FinishGltfSample(const GltfPbr& p, const GltfLobeChoice& c, vec3 wo, vec3 wi,
                             BsdfSample* s) {
  s->wi = wi;
  s->f = EvalGltfPbrLobes(p, wo, wi);
  s->pdf = PdfGltfPbrLobes(p, c, wo, wi);
  s->isDelta = false;
  s->isTransmission = wo.z * wi.z < 0.0f;
  s->passesThrough = s->isTransmission && p.thin;
  s->eta = s->isTransmission && !p.thin ? (wo.z > 0.0f ? p.glass.ior : 1.0f / p.glass.ior) : 1.0f;
  return s->pdf > 0.0f;
}

// The transmission part's sample, uc already rescaled to [0, 1) within it.
PT_HDI bool SampleGltfTransmission(const GltfPbr& p, const GltfLobeChoice& c, vec3 wo, float uc,
                                   vec2 u, BsdfSample* s) {
  if (p.thin) {
    float flip = wo.z < 0.0f ? -1.0f : 1.0f;
    vec3 w = wo * vec3(1, 1, flip);
    vec3 wm = p.smooth ? vec3(0, 0, 1) : p.ggx.SampleVisibleNormal(w, u);
    float r = FresnelDielectric(glm::dot(w, wm), p.glass.ior);
    vec3 wr = Reflect(w, wm);
    if (wr.z <= 0.0f) return false;
    bool transmits = uc >= r;
    vec3 wi = (transmits ? FlipZ(wr) : wr) * vec3(1, 1, flip);
    if (!p.smooth) return FinishGltfSample(p, c, wo, wi, s);
    s->wi = wi;
    s->f = (transmits ? p.base * (1.0f - r) : vec3(r)) * (p.transWeight / AbsCosTheta(wi));
    s->pdf = c.trans * (transmits ? 1.0f - r : r);
    s->isDelta = true;
    s->isTransmission = s->passesThrough = transmits;
    s->eta = 1.0f;
    return s->pdf > 0.0f;
  }
  BsdfSample g;
  if (!GltfTransmissionIsDelta(p)) {
    if (!SampleRoughDielectric(p.glass, wo, uc, u, &g)) return false;
    return FinishGltfSample(p, c, wo, g.wi, s);
  }
  if (!SampleSmoothDielectric(p.glass, wo, uc, &g)) return false;
  *s = g;
  s->f = g.f * p.transWeight * (g.isTransmission ? TransmissionTint(p) : vec3(1.0f));
  s->pdf = c.trans * g.pdf;
  return true;
}

// uc picks the lobe (and, rescaled, the transmission's reflect-or-refract), u the direction.
PT_HDI bool SampleGltfPbr(const Material& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  GltfPbr p = MakeGltfPbr(m);
  GltfLobeChoice c = ChooseGltfLobes(p, fabsf(wo.z));
  *s = BsdfSample{};
  if (uc >= c.spec + c.diffuse) {
    if (!(c.trans > 0.0f)) return false;
    float ut = fminf((uc - c.spec - c.diffuse) / c.trans, 0x1.fffffep-1f);
    return SampleGltfTransmission(p, c, wo, ut, u, s);
  }
  float flip = wo.z < 0.0f ? -1.0f : 1.0f;  // opaque lobes: sample the front, mirror back
  vec3 w = wo * vec3(1, 1, flip), wi;
  if (uc < c.spec) {
    if (p.smooth) {
      wi = vec3(-w.x, -w.y, w.z);
      s->f = GltfSpecularFresnel(p, w.z) / w.z;
      s->wi = wi * vec3(1, 1, flip);
      s->pdf = c.spec;
      s->isDelta = true;
      return !IsBlack(s->f);
    }
    wi = Reflect(w, p.ggx.SampleVisibleNormal(w, u));
  } else {
    wi = SampleCosineHemisphere(u);
  }
  if (wi.z <= 0.0f) return false;  // shadowed by the microfacets: single scattering loses it
  return FinishGltfSample(p, c, wo, wi * vec3(1, 1, flip), s);
}

PT_HDI bool GltfPbrHasNonDeltaLobe(const Material& m) {
  GltfPbr p = MakeGltfPbr(m);
  bool diffuse = p.coatWeight > 0.0f && !IsBlack(p.base) && p.baseNorm > 0.0f;
  bool spec = !p.smooth && (p.metallic > 0.0f || p.coatWeight > 0.0f);
  return diffuse || spec || (p.transWeight > 0.0f && !GltfTransmissionIsDelta(p));
}

}  // namespace pt
