// BSDF evaluation, pdf and importance sampling for the closed set of materials, in the local
// shading frame (z = shading normal; for dielectrics z points outside): one switch on
// MaterialType per entry point over the lobes of lobes.h, plastic.h and gltf_pbr.h.
//
// Conventions (pbrt-v4): wo and wi point away from the surface; f excludes the cosine; pdf is
// per unit solid angle for non-delta lobes. For a delta lobe pdf is the discrete probability of
// choosing it and f is chosen so that f * |cos wi| / pdf is the path weight.
// Transport mode is always radiance (camera paths), so refraction scales by 1 / eta^2.
#pragma once

#include "src/materials/gltf_pbr.h"
#include "src/materials/lobes.h"
#include "src/materials/plastic.h"

namespace pt {

// ---- Entry points ----
// kType: the material's type when the caller knows it at compile time (a shade kernel of one
// queue), so each switch below folds to that case; MaterialType::kCount reads m.type.

// f(wo, wi) without the cosine. Zero for delta lobes and for materials that reflect nothing.
template <MaterialType kType = MaterialType::kCount>
PT_HDI vec3 EvalBsdf(const Material& m, vec3 wo, vec3 wi) {
  switch (TypeOf<kType>(m)) {
    case MaterialType::kDiffuse: return EvalLambert(m, wo, wi);
    case MaterialType::kConductor:
      return IsSmooth(m) ? vec3(0.0f) : EvalRoughConductor(m, wo, wi);
    case MaterialType::kDielectric:
      return IsSmoothDielectric(m) ? vec3(0.0f) : EvalRoughDielectric(m, wo, wi);
    case MaterialType::kPlastic: return EvalPlastic(m, wo, wi);  // smooth: the base only
    case MaterialType::kGltfPbr: return EvalGltfPbr(m, wo, wi);
    case MaterialType::kEmissive:  // emits, reflects nothing
    default: return vec3(0.0f);
  }
}

// Solid-angle density with which SampleBsdf produces wi. Zero for delta lobes.
template <MaterialType kType = MaterialType::kCount>
PT_HDI float PdfBsdf(const Material& m, vec3 wo, vec3 wi) {
  switch (TypeOf<kType>(m)) {
    case MaterialType::kDiffuse: return PdfLambert(wo, wi);
    case MaterialType::kConductor: return IsSmooth(m) ? 0.0f : PdfRoughConductor(m, wo, wi);
    case MaterialType::kDielectric:
      return IsSmoothDielectric(m) ? 0.0f : PdfRoughDielectric(m, wo, wi);
    case MaterialType::kPlastic: return PdfPlastic(m, wo, wi);
    case MaterialType::kGltfPbr: return PdfGltfPbr(m, wo, wi);
    case MaterialType::kEmissive:
    default: return 0.0f;
  }
}

// Draws wi given wo; uc picks a lobe, u the direction. Returns false when the path ends here
// (absorbed, black, grazing, shadowed by the microfacets, or an emitter, which reflects
// nothing).
template <MaterialType kType = MaterialType::kCount>
PT_HDI bool SampleBsdf(const Material& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  switch (TypeOf<kType>(m)) {
    case MaterialType::kDiffuse: return SampleLambert(m, wo, u, s);
    case MaterialType::kConductor:
      return IsSmooth(m) ? SampleSmoothConductor(m, wo, s) : SampleRoughConductor(m, wo, u, s);
    case MaterialType::kDielectric:
      return IsSmoothDielectric(m) ? SampleSmoothDielectric(m, wo, uc, s)
                                   : SampleRoughDielectric(m, wo, uc, u, s);
    case MaterialType::kPlastic: return SamplePlastic(m, wo, uc, u, s);
    case MaterialType::kGltfPbr: return SampleGltfPbr(m, wo, uc, u, s);
    case MaterialType::kEmissive:
    default: return false;
  }
}

// True where next-event estimation can contribute (some lobe is not a Dirac delta): every
// plastic (its base is diffuse), rough conductors and rough glass, glTF materials with a
// diffuse base or a rough lobe.
template <MaterialType kType = MaterialType::kCount>
PT_HDI bool HasNonDeltaLobe(const Material& m) {
  switch (TypeOf<kType>(m)) {
    case MaterialType::kDiffuse: return !IsBlack(m.albedo);
    case MaterialType::kConductor: return !IsSmooth(m);
    case MaterialType::kDielectric: return !IsSmoothDielectric(m);
    case MaterialType::kPlastic: return true;
    case MaterialType::kGltfPbr: return GltfPbrHasNonDeltaLobe(m);
    case MaterialType::kEmissive:
    default: return false;
  }
}

}  // namespace pt
