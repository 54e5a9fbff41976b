// Lobe choice, pdf and sampling of gltf_layered.h's BSDF, and the layered variant's BSDF entry
// points (a switch on the material type, as bsdf.h's). One-sample MIS over the lobes: a lobe is
// drawn with probability proportional to an estimate of its albedo for wo; Eval and Pdf are the
// sums over the non-delta lobes, so a sample's f and pdf are those of its direction.
#pragma once

#include "src/materials/bsdf.h"
#include "src/materials/gltf_layered.h"

namespace pt {

struct LayeredLobeChoice {
  // Probabilities (summing to 1; all 0: nothing to sample): clearcoat, sheen, the base GGX
  // lobe, the cosine-sampled lobes (diffuse base and compensation), diffuse transmission,
  // and gltf_pbr.h's transmission.
  float coat, sheen, spec, cosine, dt, trans;
};

PT_HDI LayeredLobeChoice ChooseLayeredLobes(const GltfLayered& p, vec3 w) {  // w.z > 0
  LayeredLobeChoice c{};
  float mu = w.z, sc = CoatTransmittance(p, w);
  float muCoat = glm::dot(w, p.coatFrame.z);
  if (p.coat > 0.0f && muCoat > 0.0f) c.coat = p.coat * p.coatAlbedo.At(muCoat);
  float sheen = p.sheenMax * fminf(1.0f, SheenAlbedo(p, mu));
  c.sheen = sc * sheen;
  float below = sc * (1.0f - sheen);
  c.spec = below * Luminance(BaseSpecFresnel(p, mu));
  float base = p.baseNorm > 0.0f ? below * p.core.coatWeight * (1.0f - DielectricAlbedo(p, mu)) : 0.0f;
  c.cosine = base * (1.0f - p.dt) * Luminance(p.core.base);
  if (p.msNorm > 0.0f)
    c.cosine += below * p.core.metallic * Luminance(p.fms) * (1.0f - GgxAlbedoExact(mu, p.roughness));
  c.dt = base * p.dt * Luminance(p.dtColor);
  if (p.core.transWeight > 0.0f) {
    float r = FresnelDielectric(mu, p.core.glass.ior);
    c.trans = below * p.core.transWeight *
              (r + (1.0f - r) * fmaxf(Luminance(TransmissionTint(p.core)), 0.05f));
  }
  float sum = c.coat + c.sheen + c.spec + c.cosine + c.dt + c.trans;
  if (!(sum > 0.0f)) return LayeredLobeChoice{};
  float inv = 1.0f / sum;
  return LayeredLobeChoice{c.coat * inv, c.sheen * inv, c.spec * inv,
                           c.cosine * inv, c.dt * inv, c.trans * inv};
}

PT_HDI float PdfGltfLayeredLobes(const GltfLayered& p, const LayeredLobeChoice& c, vec3 wo,
                                 vec3 wi) {
  float pdf = c.trans > 0.0f ? c.trans * PdfGltfTransmission(p.core, wo, wi) : 0.0f;
  if (wo.z < 0.0f) wo = FlipZ(wo), wi = FlipZ(wi);
  if (wo.z <= 0.0f) return pdf;
  if (wi.z > 0.0f) {
    pdf += c.cosine * CosineHemispherePdf(wi.z);
    if (c.coat > 0.0f) pdf += c.coat * CoatLobePdf(p, wo, wi);
    if (c.sheen > 0.0f) pdf += c.sheen * p.sheen.ReflectionPdf(wo, wi);
    vec3 wm;
    if (c.spec > 0.0f && !p.specSmooth && ReflectionHalfVector(wo, wi, &wm))
      pdf += c.spec * p.spec.ReflectionPdf(wo, wm);
  } else if (wi.z < 0.0f) {
    pdf += c.dt * CosineHemispherePdf(-wi.z);
  }
  return pdf;
}

// A non-delta direction's record: f and pdf of the whole mixture there.
PT_HDI bool FinishLayeredSample(const GltfLayered& p, const LayeredLobeChoice& c, vec3 wo,
                                vec3 wi, bool passesThrough, BsdfSample* s) {
  s->wi = wi;
  s->f = EvalGltfLayeredLobes(p, wo, wi);
  s->pdf = PdfGltfLayeredLobes(p, c, wo, wi);
  s->isDelta = false;
  s->isTransmission = wo.z * wi.z < 0.0f;
  s->passesThrough = s->isTransmission && (passesThrough || p.core.thin);
  s->eta = s->isTransmission && !s->passesThrough
               ? (wo.z > 0.0f ? p.core.glass.ior : 1.0f / p.core.glass.ior)
               : 1.0f;
  return s->pdf > 0.0f;
}

// gltf_pbr.h's transmission sample (uc rescaled within it), scaled by the layers above.
PT_HDI bool SampleLayeredTransmission(const GltfLayered& p, const LayeredLobeChoice& c, vec3 wo,
                                      float uc, vec2 u, BsdfSample* s) {
  GltfLobeChoice only{0.0f, 0.0f, 1.0f};
  if (!SampleGltfTransmission(p.core, only, wo, uc, u, s)) return false;
  if (!s->isDelta) return FinishLayeredSample(p, c, wo, s->wi, false, s);
  s->f *= BelowLayers(p, wo, s->wi) * TransmissionFilm(p, wo, s->wi);
  s->pdf *= c.trans;
  return s->pdf > 0.0f && !IsBlack(s->f);
}

// A mirror lobe's sample (the smooth coat, or the smooth base lobe) for w on the front.
PT_HDI bool LayeredMirror(vec3 wi, vec3 weight, float pdf, float flip, BsdfSample* s) {
  if (wi.z <= 0.0f) return false;
  s->wi = wi * vec3(1.0f, 1.0f, flip);
  s->f = weight / wi.z;
  s->pdf = pdf;
  s->isDelta = true;
  return pdf > 0.0f && !IsBlack(s->f);
}

// The front-side lobes (all but transmission); uc already rescaled to the opaque lobes' range.
PT_HDI bool SampleLayeredOpaque(const GltfLayered& p, const LayeredLobeChoice& c, vec3 wo,
                                float uc, vec2 u, BsdfSample* s) {
  float flip = wo.z < 0.0f ? -1.0f : 1.0f;
  vec3 w = wo * vec3(1.0f, 1.0f, flip), wi;
  bool through = false;
  if (uc < c.coat) {
    vec3 o = p.coatFrame.ToLocal(w);
    if (o.z <= 0.0f) return false;
    if (p.coatSmooth) {
      float f = p.coat * (kCoatF0 + (1.0f - kCoatF0) * SchlickWeight(o.z));
      return LayeredMirror(p.coatFrame.FromLocal(vec3(-o.x, -o.y, o.z)), vec3(f), c.coat, flip, s);
    }
    vec3 i = Reflect(o, p.coatGgx.SampleVisibleNormal(o, u));
    if (i.z <= 0.0f) return false;
    wi = p.coatFrame.FromLocal(i);
  } else if (uc < c.coat + c.sheen) {
    wi = Reflect(w, p.sheen.SampleNormal(u));
  } else if (uc < c.coat + c.sheen + c.spec) {
    if (p.specSmooth) {
      wi = vec3(-w.x, -w.y, w.z);
      vec3 f = BaseSpecFresnel(p, w.z) * BelowLayers(p, w, wi);
      return LayeredMirror(wi, f, c.spec, flip, s);
    }
    wi = Reflect(w, p.spec.SampleVisibleNormal(w, u));
  } else if (uc < c.coat + c.sheen + c.spec + c.cosine) {
    wi = SampleCosineHemisphere(u);
  } else {
    wi = FlipZ(SampleCosineHemisphere(u));  // diffuse transmission: through a thin surface
    through = true;
  }
  if (!through && wi.z <= 0.0f) return false;
  return FinishLayeredSample(p, c, wo, wi * vec3(1.0f, 1.0f, flip), through, s);
}

PT_HDI bool SampleGltfLayeredLobes(const GltfLayered& p, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  if (wo.z == 0.0f) return false;
  LayeredLobeChoice c = ChooseLayeredLobes(p, wo.z < 0.0f ? FlipZ(wo) : wo);
  *s = BsdfSample{};
  float opaque = 1.0f - c.trans;
  if (uc >= opaque) {
    if (!(c.trans > 0.0f)) return false;
    return SampleLayeredTransmission(p, c, wo, fminf((uc - opaque) / c.trans, 0x1.fffffep-1f), u, s);
  }
  return SampleLayeredOpaque(p, c, wo, uc, u, s);
}

PT_HDI bool GltfLayeredHasNonDeltaLobe(const GltfLayered& p) {
  bool base = p.core.coatWeight > 0.0f && p.baseNorm > 0.0f &&
              (!IsBlack(p.core.base) || (p.dt > 0.0f && !IsBlack(p.dtColor)));
  bool spec = !p.specSmooth && (p.core.metallic > 0.0f || p.core.coatWeight > 0.0f);
  bool coat = p.coat > 0.0f && !p.coatSmooth;
  return base || spec || coat || p.sheenMax > 0.0f || p.msNorm > 0.0f ||
         (p.core.transWeight > 0.0f && !GltfTransmissionIsDelta(p.core));
}

// ---- The layered variant's entry points ----
// glTF materials with extensions, unlit or energy compensation, and conductors with energy
// compensation (a glTF metal: the same lobe) run the layered BSDF; everything else bsdf.h's.

PT_HDI bool UnlitMaterial(const Material& m) {
  return m.type == MaterialType::kGltfPbr && (m.flags & kMaterialUnlit) != 0;
}

// The layered BSDF's constants for m: a compensated conductor is a glTF metal.
PT_HDI GltfLayered LayeredOf(const LayeredMaterial& m) {
  if (m.type != MaterialType::kConductor) return MakeGltfLayered(m);
  LayeredMaterial metal = m;
  metal.type = MaterialType::kGltfPbr;
  metal.metallic = 1.0f;
  metal.transmission = 0.0f;
  metal.layers = GltfLayers{};
  return MakeGltfLayered(metal);
}

template <MaterialType kType>
PT_HDI bool RunsLayered(const LayeredMaterial& m) {
  switch (TypeOf<kType>(m)) {
    case MaterialType::kGltfPbr: return UsesLayers(m);
    case MaterialType::kConductor:
      return (m.flags & kMaterialEnergyCompensation) != 0 && !IsSmooth(m);
    default: return false;
  }
}

template <MaterialType kType = MaterialType::kCount>
PT_HDI vec3 EvalLayeredBsdf(const LayeredMaterial& m, vec3 wo, vec3 wi) {
  if (!RunsLayered<kType>(m)) return EvalBsdf<kType>(m, wo, wi);
  if (UnlitMaterial(m) || wo.z == 0.0f) return vec3(0.0f);
  return EvalGltfLayeredLobes(LayeredOf(m), wo, wi);
}

template <MaterialType kType = MaterialType::kCount>
PT_HDI float PdfLayeredBsdf(const LayeredMaterial& m, vec3 wo, vec3 wi) {
  if (!RunsLayered<kType>(m)) return PdfBsdf<kType>(m, wo, wi);
  if (UnlitMaterial(m) || wo.z == 0.0f) return 0.0f;
  GltfLayered p = LayeredOf(m);
  return PdfGltfLayeredLobes(p, ChooseLayeredLobes(p, wo.z < 0.0f ? FlipZ(wo) : wo), wo, wi);
}

template <MaterialType kType = MaterialType::kCount>
PT_HDI bool SampleLayeredBsdf(const LayeredMaterial& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  if (!RunsLayered<kType>(m)) return SampleBsdf<kType>(m, wo, uc, u, s);
  if (UnlitMaterial(m)) return false;
  return SampleGltfLayeredLobes(LayeredOf(m), wo, uc, u, s);
}

template <MaterialType kType = MaterialType::kCount>
PT_HDI bool LayeredHasNonDeltaLobe(const LayeredMaterial& m) {
  if (!RunsLayered<kType>(m)) return HasNonDeltaLobe<kType>(m);
  if (UnlitMaterial(m)) return false;
  return GltfLayeredHasNonDeltaLobe(LayeredOf(m));
}

}  // namespace pt
