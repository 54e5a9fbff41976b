// The BSDF calls of the shade stage, per feature class. The diffuse variant calls the
// Lambertian lobe directly and the smooth variant adds only the delta lobes, so their kernels
// contain no microfacet, plastic, glTF or texture code at all; the general variant dispatches
// over every material. Each variant computes exactly what the general one does for the materials
// it admits (same functions, same order), so images are bit-identical on the CPU.
//
// Q is the shade queue a kernel serves (src/integrator/shade_queues.h), or kAnyQueue: in a
// queue's kernel the material type is a compile-time constant (kQueueType<Q>), so every switch
// on it folds to one case, and untextured queues compile no texture lookups.
#pragma once

#include <type_traits>

#include "src/materials/bsdf.h"
#include "src/integrator/shade_queues.h"
#include "src/materials/gltf_layered_sample.h"
#include "src/materials/resolve.h"
#include "src/materials/resolve_layers.h"
#include "src/scene/effects.h"

namespace pt {

// What the shade stage holds at a hit: the material, and in the layered variant its glTF
// extension parameters too (src/materials/layered_material.h).
template <FeatureClass C>
using HitMaterial = std::conditional_t<C == FeatureClass::kLayered, LayeredMaterial, Material>;

// The material at the hit; the general variant applies textures (and normal maps, which move
// si->ns).
template <FeatureClass C, uint32_t Q>
PT_HDI HitMaterial<C> MaterialAt(const SceneView& s, PrimRef ref, SurfaceInteraction* si) {
  if constexpr (C == FeatureClass::kLayered) {
    vec3 nsBase = si->ns;  // the clearcoat's normal ignores the base normal texture
    LayeredMaterial m =
        MakeLayered(ResolveMaterial<kQueueType<Q>, Q == kAnyQueue || QueueTextured(Q)>(s, ref, si));
    if (TypeOf<kQueueType<Q>>(m) == MaterialType::kGltfPbr) ResolveGltfLayers(s, ref, *si, nsBase, &m);
    return m;
  } else if constexpr (C == FeatureClass::kGeneral) {
    return ResolveMaterial<kQueueType<Q>, Q == kAnyQueue || QueueTextured(Q)>(s, ref, si);
  } else {
    return s.materials[si->material];
  }
}

// The layered variant's material directions into the shading frame (nothing elsewhere).
template <FeatureClass C>
PT_HDI void LocalizeMaterial(const Frame& frame, HitMaterial<C>* m) {
  if constexpr (C == FeatureClass::kLayered) LocalizeLayers(frame, m);
}

// Whether m has type t, constant in a queue's kernel.
template <uint32_t Q>
PT_HDI bool IsType(const Material& m, MaterialType t) {
  return TypeOf<kQueueType<Q>>(m) == t;
}

template <FeatureClass C, uint32_t Q>
PT_HDI vec3 EvalBsdfFor(const HitMaterial<C>& m, vec3 wo, vec3 wi) {
  if constexpr (C == FeatureClass::kLayered) return EvalLayeredBsdf<kQueueType<Q>>(m, wo, wi);
  else if constexpr (C == FeatureClass::kGeneral) return EvalBsdf<kQueueType<Q>>(m, wo, wi);
  else return IsType<Q>(m, MaterialType::kDiffuse) ? EvalLambert(m, wo, wi) : vec3(0.0f);
}

template <FeatureClass C, uint32_t Q>
PT_HDI float PdfBsdfFor(const HitMaterial<C>& m, vec3 wo, vec3 wi) {
  if constexpr (C == FeatureClass::kLayered) return PdfLayeredBsdf<kQueueType<Q>>(m, wo, wi);
  else if constexpr (C == FeatureClass::kGeneral) return PdfBsdf<kQueueType<Q>>(m, wo, wi);
  else return IsType<Q>(m, MaterialType::kDiffuse) ? PdfLambert(wo, wi) : 0.0f;
}

template <FeatureClass C, uint32_t Q>
PT_HDI bool SampleBsdfFor(const HitMaterial<C>& m, vec3 wo, float uc, vec2 u, BsdfSample* s) {
  if constexpr (C == FeatureClass::kLayered) {
    return SampleLayeredBsdf<kQueueType<Q>>(m, wo, uc, u, s);
  } else if constexpr (C == FeatureClass::kGeneral) {
    return SampleBsdf<kQueueType<Q>>(m, wo, uc, u, s);
  } else if constexpr (C == FeatureClass::kSmooth) {
    switch (TypeOf<kQueueType<Q>>(m)) {
      case MaterialType::kDiffuse: return SampleLambert(m, wo, u, s);
      case MaterialType::kConductor: return SampleSmoothConductor(m, wo, s);
      case MaterialType::kDielectric: return SampleSmoothDielectric(m, wo, uc, s);
      default: return false;
    }
  } else {
    return IsType<Q>(m, MaterialType::kDiffuse) && SampleLambert(m, wo, u, s);
  }
}

template <FeatureClass C, uint32_t Q>
PT_HDI bool HasNonDeltaLobeFor(const HitMaterial<C>& m) {
  if constexpr (C == FeatureClass::kLayered) return LayeredHasNonDeltaLobe<kQueueType<Q>>(m);
  else if constexpr (C == FeatureClass::kGeneral) return HasNonDeltaLobe<kQueueType<Q>>(m);
  else return IsType<Q>(m, MaterialType::kDiffuse) && !IsBlack(m.albedo);
}

// Media exist only where light can refract into glass.
template <FeatureClass C>
constexpr bool kHasMedia = C != FeatureClass::kDiffuse;

}  // namespace pt
