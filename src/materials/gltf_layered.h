// The glTF material with its extension lobes (docs/gltf-materials.md has the formulas and the
// reasons), in the local shading frame, built on gltf_pbr.h's core:
//
//   f = coat + Sc(o) Sc(i) [ sheen + Ssh(o, i) core ]
//   core = m metal + (1 - m) [(1 - t) dielectric + t transmission]
//   dielectric = F_d spec + T(o) T(i) / (1 - E_d,avg) [(1 - dt) base / pi  |  dt dtColor / pi]
//
//   coat      KHR_materials_clearcoat: GGX about the coat normal, Schlick F0 = 0.04, times the
//             clearcoat factor; what it reflects is taken from everything below, reciprocally:
//             Sc(w) = 1 - clearcoat E_coat(w . n_coat) per crossing.
//   sheen     KHR_materials_sheen: charlie_sheen.h, its albedo scaling exactly the extension's,
//             Ssh(o, i) = min(1 - max(sheenColor) E_sh(mu_o), 1 - max(sheenColor) E_sh(mu_i)).
//   spec      the base GGX lobe, anisotropic by KHR_materials_anisotropy (ggx_aniso.h).
//   metal     Schlick from the base colour; mixed with the thin-film Fresnel by
//             KHR_materials_iridescence (thin_film.h); plus, with energy compensation, Kulla and
//             Conty's multiple-scattering lobe (energy compensation in the docs).
//   F_d       KHR_materials_specular: Schlick from min(F0(ior) specularColor, 1) specular to
//             F90 = specular, mixed with the thin film by iridescence.
//   T(w)      1 - E_d(w): the albedo the dielectric's specular lobe leaves (max channel), so
//             the diffuse base's albedo is exactly base T(mu_o) (gltf_pbr.h's construction).
//   dt        KHR_materials_diffuse_transmission: Lambertian transmission to the other side.
//
// The opaque lobes are two-sided (the back mirrors the front); the transmission part is
// gltf_pbr.h's, scaled by the layers above it. Eval and Pdf are sums over the non-delta lobes.
#pragma once

#include "src/materials/charlie_sheen.h"
#include "src/materials/ggx_aniso.h"
#include "src/materials/gltf_pbr.h"
#include "src/materials/layer_albedo.h"
#include "src/materials/layered_material.h"
#include "src/materials/thin_film.h"

namespace pt {

constexpr float kCoatF0 = 0.04f;  // the clearcoat's ior 1.5

struct GltfLayered {
  GltfPbr core;  // base, metallic, dielectric and transmission weights, the transmission lobe
  float roughness;
  AnisoGgx spec;
  bool specSmooth;
  vec3 f0d;  // dielectric Fresnel: F0 (coloured) and F90
  float f90d, f0dMax;
  float irid, filmIor, thickness;
  float dt;
  vec3 dtColor;
  float baseNorm;  // 1 / (pi (1 - E_d,avg)), 0 when the dielectric lobe reflects everything
  vec3 fms;        // metal energy compensation: Kulla-Conty's F_ms (0: off)
  float msNorm;    // 1 / (pi (1 - E_avg))
  vec3 sheenColor;
  float sheenMax, sheenRoughness;
  CharlieSheen sheen;
  float coat;  // clearcoat factor (0: none)
  GgxDistribution coatGgx;
  bool coatSmooth;
  Frame coatFrame;  // z = the coat normal
  CoatAlbedo coatAlbedo;
};

// ---- Fresnel terms ----

PT_HDI vec3 SchlickF0F90(vec3 f0, vec3 f90, float c) {
  return f0 + (f90 - f0) * SchlickWeight(c);
}

PT_HDI vec3 MetalFresnel(const GltfLayered& p, float c) {
  vec3 f = SchlickF0F90(p.core.base, vec3(1.0f), c);
  if (p.irid > 0.0f)
    f += p.irid * (ThinFilmFresnel(p.filmIor, p.thickness, p.core.base, c) - f);
  return f;
}

PT_HDI vec3 DielectricFresnel(const GltfLayered& p, float c) {
  vec3 f = SchlickF0F90(p.f0d, vec3(p.f90d), c);
  if (p.irid > 0.0f) f += p.irid * (ThinFilmFresnel(p.filmIor, p.thickness, p.f0d, c) - f);
  return f;
}

// Fresnel of the base GGX lobe: the metal and dielectric parts by their weights.
PT_HDI vec3 BaseSpecFresnel(const GltfLayered& p, float c) {
  vec3 f(0.0f);
  if (p.core.metallic > 0.0f) f += p.core.metallic * MetalFresnel(p, c);
  if (p.core.coatWeight > 0.0f) f += p.core.coatWeight * DielectricFresnel(p, c);
  return f;
}

// ---- Albedos the layers are scaled by ----

// Upper bound of the dielectric specular lobe's albedo at cosine mu (max channel). With
// iridescence the thin film's share is estimated as its reflectance at mu times the lobe's
// F = 1 albedo (exact for smooth surfaces).
PT_HDI float DielectricAlbedo(const GltfLayered& p, float mu) {
  vec2 e = GgxAlbedoBounds(mu, p.roughness, p.specSmooth);
  float a = p.f0dMax * e.x + (p.f90d - p.f0dMax) * e.y;
  if (p.irid > 0.0f)
    a += p.irid * (e.x * MaxComponent(ThinFilmFresnel(p.filmIor, p.thickness, p.f0d, mu)) - a);
  return fminf(a, 1.0f);
}

// Its hemispherical average; the thin film's by an 8-point Gauss-Legendre rule in mu.
PT_HDI float DielectricAlbedoAverage(const GltfLayered& p) {
  vec2 e = GgxAlbedoBoundAverages(p.roughness, p.specSmooth);
  float a = p.f0dMax * e.x + (p.f90d - p.f0dMax) * e.y;
  if (p.irid > 0.0f) {
    const float x[4] = {0.1834346425f, 0.5255324099f, 0.7966664774f, 0.9602898565f};
    const float w[4] = {0.3626837834f, 0.3137066459f, 0.2223810345f, 0.1012285363f};
    float film = 0.0f;
    for (int k = 0; k < 8; ++k) {
      float mu = 0.5f + 0.5f * (k < 4 ? -x[k] : x[k - 4]);
      float ex = GgxAlbedoBounds(mu, p.roughness, p.specSmooth).x;
      film += w[k & 3] * mu * ex * MaxComponent(ThinFilmFresnel(p.filmIor, p.thickness, p.f0d, mu));
    }
    a += p.irid * (film - a);  // 2 * (1/2) sum w mu E: the rule on [0, 1]
  }
  return fminf(a, 1.0f);
}

// Sc: what the clearcoat lets through at direction w (front side).
PT_HDI float CoatTransmittance(const GltfLayered& p, vec3 w) {
  if (p.coat <= 0.0f) return 1.0f;
  return 1.0f - p.coat * p.coatAlbedo.At(fmaxf(glm::dot(w, p.coatFrame.z), 0.0f));
}

// The sheen's albedo at cosine mu (at most 1: the lobe is normalised where it exceeds 1).
PT_HDI float SheenAlbedo(const GltfLayered& p, float mu) {
  return p.sheenMax > 0.0f ? SheenAlbedoBound(mu, p.sheenRoughness) : 0.0f;
}

// Everything below the coat is scaled by Sc(o) Sc(i); below the sheen also by Ssh(o, i).
struct LayerScale {
  float coat, sheen;
};

PT_HDI LayerScale LayerScaleOf(const GltfLayered& p, vec3 wo, vec3 wi) {
  float sh = 1.0f;
  if (p.sheenMax > 0.0f)
    sh = 1.0f - p.sheenMax * fminf(1.0f, fmaxf(SheenAlbedo(p, wo.z), SheenAlbedo(p, wi.z)));
  return LayerScale{CoatTransmittance(p, wo) * CoatTransmittance(p, wi), sh};
}

// ---- Construction ----

PT_HDI void SetDielectric(const LayeredMaterial& m, GltfLayered* p) {
  const GltfLayers& x = m.layers;
  float w = (x.mask & kExtSpecular) ? fmaxf(x.specular, 0.0f) : 1.0f;
  vec3 color = (x.mask & kExtSpecular) ? glm::max(x.specularColor, vec3(0.0f)) : vec3(1.0f);
  p->f0d = glm::min(p->core.f0 * color, vec3(1.0f)) * w;
  p->f90d = fminf(w, 1.0f);
  p->f0dMax = fminf(MaxComponent(p->f0d), p->f90d);
  p->irid = (x.mask & kExtIridescence) ? Clamp01(x.iridescence) : 0.0f;
  p->filmIor = x.iridescenceIor;
  p->thickness = fmaxf(x.thickness, 0.0f);
  p->dt = (x.mask & kExtDiffuseTransmission) ? Clamp01(x.diffuseTransmission) : 0.0f;
  p->dtColor = glm::clamp(x.diffuseTransmissionColor, vec3(0.0f), vec3(1.0f));
  float avg = p->core.coatWeight > 0.0f ? DielectricAlbedoAverage(*p) : 1.0f;
  p->baseNorm = avg < 1.0f ? kInvPi / (1.0f - avg) : 0.0f;
}

// Kulla and Conty 2017: the metal lobe's missing energy 1 - E(mu) returned by a lobe of shape
// (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)), coloured by F_ms = F_avg^2 E_avg /
// (1 - F_avg (1 - E_avg)) (Schlick's F_avg = F0 + (1 - F0) / 21).
PT_HDI void SetCompensation(const LayeredMaterial& m, GltfLayered* p) {
  p->fms = vec3(0.0f);
  p->msNorm = 0.0f;
  if (!(m.flags & kMaterialEnergyCompensation) || p->core.metallic <= 0.0f || p->specSmooth) return;
  float eAvg = GgxAlbedoExactAverage(p->roughness);
  if (!(eAvg < 1.0f)) return;
  vec3 fAvg = p->core.base + (vec3(1.0f) - p->core.base) / 21.0f;
  p->fms = fAvg * fAvg * eAvg / (vec3(1.0f) - fAvg * (1.0f - eAvg));
  p->msNorm = kInvPi / (1.0f - eAvg);
}

PT_HDI GltfLayered MakeGltfLayered(const LayeredMaterial& m) {
  GltfLayered p;
  p.core = MakeGltfPbr(m);
  const GltfLayers& x = m.layers;
  p.roughness = Clamp01(m.roughness);
  float alpha = GgxAlpha(p.roughness);
  p.spec = AnisoGgx::Isotropic(alpha);
  if ((x.mask & kExtAnisotropy) && x.anisotropy > 0.0f) {
    // alphaB at least the mirror threshold: a smooth material made anisotropic is a rough lobe
    // (alphaT = strength^2) whose D must stay finite across the direction.
    float s = Clamp01(x.anisotropy);
    p.spec = AnisoGgx{alpha + (1.0f - alpha) * s * s, fmaxf(alpha, kSmoothAlpha),
                      x.anisotropyDir.x, x.anisotropyDir.y};
  }
  p.specSmooth = p.spec.Smooth();
  SetDielectric(m, &p);
  SetCompensation(m, &p);
  p.sheenColor = (x.mask & kExtSheen) ? glm::clamp(x.sheenColor, vec3(0.0f), vec3(1.0f)) : vec3(0.0f);
  p.sheenMax = MaxComponent(p.sheenColor);
  p.sheenRoughness = Clamp01(x.sheenRoughness);
  p.sheen = CharlieSheen::FromRoughness(p.sheenRoughness);
  p.coat = (x.mask & kExtClearcoat) ? Clamp01(x.clearcoat) : 0.0f;
  float cr = Clamp01(x.clearcoatRoughness);
  p.coatGgx.alpha = GgxAlpha(cr);
  p.coatSmooth = IsEffectivelySmooth(cr);
  p.coatFrame = Frame::FromZ(p.coat > 0.0f ? x.coatNormal : vec3(0.0f, 0.0f, 1.0f));
  p.coatAlbedo = CoatAlbedo{kCoatF0, cr, p.coatSmooth};
  return p;
}

// ---- The lobes, for wo on the front (wo.z > 0) ----

PT_HDI float CoatLobe(const GltfLayered& p, vec3 wo, vec3 wi) {
  if (p.coat <= 0.0f || p.coatSmooth) return 0.0f;
  vec3 o = p.coatFrame.ToLocal(wo), i = p.coatFrame.ToLocal(wi), wm;
  if (o.z <= 0.0f || i.z <= 0.0f || !ReflectionHalfVector(o, i, &wm)) return 0.0f;
  float f = kCoatF0 + (1.0f - kCoatF0) * SchlickWeight(glm::dot(o, wm));
  return p.coat * f * p.coatGgx.D(wm) * p.coatGgx.G(o, i) / (4.0f * o.z * i.z);
}

PT_HDI float CoatLobePdf(const GltfLayered& p, vec3 wo, vec3 wi) {
  if (p.coat <= 0.0f || p.coatSmooth) return 0.0f;
  vec3 o = p.coatFrame.ToLocal(wo), i = p.coatFrame.ToLocal(wi), wm;
  if (o.z <= 0.0f || i.z <= 0.0f || !ReflectionHalfVector(o, i, &wm)) return 0.0f;
  return p.coatGgx.ReflectionPdf(o, wm);
}

// The sheen lobe, normalised where its albedo would exceed 1 (reciprocal: both directions).
PT_HDI vec3 SheenLobe(const GltfLayered& p, vec3 wo, vec3 wi) {
  if (p.sheenMax <= 0.0f) return vec3(0.0f);
  float norm = fmaxf(1.0f, fmaxf(SheenAlbedo(p, wo.z), SheenAlbedo(p, wi.z)));
  return p.sheenColor * (p.sheen.Eval(wo, wi) / norm);
}

// The dielectric's diffuse base per unit colour: T(o) T(i) / (pi (1 - E_d,avg)).
PT_HDI float BaseScale(const GltfLayered& p, float muO, float muI) {
  if (p.core.coatWeight <= 0.0f || p.baseNorm <= 0.0f) return 0.0f;
  return p.core.coatWeight * (1.0f - DielectricAlbedo(p, muO)) * (1.0f - DielectricAlbedo(p, muI)) *
         p.baseNorm;
}

// The core's lobes on the front side: GGX, the diffuse base, the compensation lobe.
PT_HDI vec3 CoreReflection(const GltfLayered& p, vec3 wo, vec3 wi) {
  vec3 f = p.core.base * ((1.0f - p.dt) * BaseScale(p, wo.z, wi.z));
  vec3 wm;
  if (!p.specSmooth) {
    float dg = p.spec.Reflection(wo, wi, &wm);
    if (dg > 0.0f) f += BaseSpecFresnel(p, glm::dot(wo, wm)) * dg;
  }
  if (p.msNorm > 0.0f) {
    float eo = GgxAlbedoExact(wo.z, p.roughness), ei = GgxAlbedoExact(wi.z, p.roughness);
    f += p.fms * (p.core.metallic * (1.0f - eo) * (1.0f - ei) * p.msNorm);
  }
  return f;
}

// ---- Eval ----

// KHR_materials_iridescence on the transmission part: its reflection takes the film's
// Fresnel instead of the glass's (mixed by the iridescence factor), its transmission what the
// film's largest channel leaves, both relative to the glass Fresnel r that chose between them,
// at the cosine on the air side: a thin wall's pair's mean (exact when smooth; reciprocal); a
// volume's outside direction when light crosses, wo's when it reflects outside. Reflections
// inside a volume keep the glass's Fresnel.
PT_HDI vec3 TransmissionFilm(const GltfLayered& p, vec3 wo, vec3 wi) {
  if (p.irid <= 0.0f) return vec3(1.0f);
  bool crosses = wo.z * wi.z < 0.0f;
  float c = 0.5f * (fabsf(wo.z) + fabsf(wi.z));
  if (!p.core.thin) {
    if (!crosses && wo.z < 0.0f) return vec3(1.0f);
    c = crosses ? fmaxf(wo.z, wi.z) : wo.z;
  }
  float r = FresnelDielectric(c, p.core.glass.ior);
  vec3 f = vec3(r) + p.irid * (ThinFilmFresnel(p.filmIor, p.thickness, p.f0d, c) - vec3(r));
  if (!crosses) return r > 0.0f ? f / r : vec3(1.0f);
  return vec3(r < 1.0f ? fmaxf(0.0f, 1.0f - MaxComponent(f)) / (1.0f - r) : 1.0f);
}

// The layers' scale for a pair, both mirrored to the front (the layers are two-sided).
PT_HDI float BelowLayers(const GltfLayered& p, vec3 wo, vec3 wi) {
  LayerScale s = LayerScaleOf(p, wo.z < 0.0f ? FlipZ(wo) : wo, wi.z < 0.0f ? FlipZ(wi) : wi);
  return s.coat * s.sheen;
}

PT_HDI vec3 EvalGltfLayeredLobes(const GltfLayered& p, vec3 wo, vec3 wi) {
  vec3 f = EvalGltfTransmission(p.core, wo, wi);  // any sides; zero without transmission
  if (p.core.transWeight > 0.0f) f *= TransmissionFilm(p, wo, wi);
  if (wo.z < 0.0f) wo = FlipZ(wo), wi = FlipZ(wi);  // the opaque lobes are two-sided
  vec3 wiFront = wi.z < 0.0f ? FlipZ(wi) : wi;
  LayerScale s = LayerScaleOf(p, wo, wiFront);
  float below = s.coat * s.sheen;
  f *= below;
  if (wi.z > 0.0f) {
    f += vec3(CoatLobe(p, wo, wi)) + s.coat * SheenLobe(p, wo, wi);
    f += below * CoreReflection(p, wo, wi);
  } else if (wi.z < 0.0f && p.dt > 0.0f) {
    f += p.dtColor * (below * p.dt * BaseScale(p, wo.z, -wi.z));
  }
  return f;
}

}  // namespace pt
