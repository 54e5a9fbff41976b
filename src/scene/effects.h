// The effects a scene calls for: what its materials, lights and camera need simulated. The
// renderer reports them and runs stage variants that compile out what is absent.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

enum Effect : uint32_t {
  kEffectDiffuse = 1u << 0,
  kEffectEmissive = 1u << 1,
  kEffectConductor = 1u << 2,
  kEffectDielectric = 1u << 3,
  kEffectPlastic = 1u << 4,
  kEffectAbsorption = 1u << 5,
  kEffectRoughLobes = 1u << 6,
  kEffectTextures = 1u << 7,
  kEffectDepthOfField = 1u << 8,
  kEffectAreaLights = 1u << 9,
  kEffectPointLights = 1u << 10,
  kEffectBackgroundLight = 1u << 11,
  kEffectGltfPbr = 1u << 12,            // the glTF metallic-roughness material
  kEffectNormalMaps = 1u << 13,
  kEffectAlpha = 1u << 14,              // alpha MASK / BLEND (the intersector's hit test)
  kEffectTransmission = 1u << 15,       // glTF transmission (thin walls or volumes)
  kEffectEmissiveTextures = 1u << 16,
  kEffectBackfaceCulling = 1u << 17,    // single-sided glTF materials (the intersector's)
};

// Effects of the materials some primitive uses, the lights and the camera.
uint32_t AnalyzeEffects(const Scene& scene);

// Names for the statistics and the log line ("diffuse", "area_lights", ...).
std::vector<std::string> EffectNames(uint32_t effects);

// The handful of stage variants: each compiles only the code its effects need.
enum class FeatureClass : uint32_t {
  kDiffuse = 0,  // Lambertian and emitters only: no Fresnel, microfacets, media or textures
  kSmooth = 1,   // adds smooth mirrors and glass (Fresnel, refraction, absorption)
  kGeneral = 2,  // everything: rough lobes, plastic, glTF materials, textures, normal maps
};

FeatureClass ChooseFeatureClass(uint32_t effects);
const char* FeatureClassName(FeatureClass c);

}  // namespace pt
