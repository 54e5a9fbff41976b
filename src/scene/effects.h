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
  kEffectDirectionalLights = 1u << 12,  // distant lights: delta, or a cone (a sun disk)
  kEffectEnvironmentMap = 1u << 13,     // an image (or baked sky) environment: map code runs
  kEffectGltfPbr = 1u << 14,            // the glTF metallic-roughness material
  kEffectNormalMaps = 1u << 15,
  kEffectAlpha = 1u << 16,              // alpha MASK / BLEND (the intersector's hit test)
  kEffectTransmission = 1u << 17,       // glTF transmission (thin walls or volumes)
  kEffectEmissiveTextures = 1u << 18,
  kEffectBackfaceCulling = 1u << 19,    // single-sided glTF materials (the intersector's)
  kEffectSpotLights = 1u << 20,
  // The glTF extension lobes (src/materials/gltf_layered.h) and energy compensation: each
  // makes the scene run the layered variant.
  kEffectSpecular = 1u << 21,
  kEffectClearcoat = 1u << 22,
  kEffectSheen = 1u << 23,
  kEffectIridescence = 1u << 24,
  kEffectAnisotropy = 1u << 25,
  kEffectDiffuseTransmission = 1u << 26,
  kEffectUnlit = 1u << 27,
  kEffectEnergyCompensation = 1u << 28,
  kEffectMedia = 1u << 29,              // participating media: the media stages run (src/media/)
};

// The effects only the layered variant runs.
constexpr uint32_t kLayeredEffects = kEffectSpecular | kEffectClearcoat | kEffectSheen |
                                     kEffectIridescence | kEffectAnisotropy |
                                     kEffectDiffuseTransmission | kEffectUnlit |
                                     kEffectEnergyCompensation;

// Effects of the materials some primitive uses, the lights and the camera.
uint32_t AnalyzeEffects(const Scene& scene);

// Names for the statistics and the log line ("diffuse", "area_lights", ...).
std::vector<std::string> EffectNames(uint32_t effects);

// The handful of stage variants: each compiles only the code its effects need.
enum class FeatureClass : uint32_t {
  kDiffuse = 0,  // Lambertian and emitters only: no Fresnel, microfacets, media or textures
  kSmooth = 1,   // adds smooth mirrors and glass (Fresnel, refraction, absorption)
  kGeneral = 2,  // everything: rough lobes, plastic, glTF materials, textures, normal maps
  kLayered = 3,  // the general variant plus the glTF extension lobes and energy compensation
};

// At least the general class (the class holding every effect but the layered ones).
constexpr bool IsGeneralClass(FeatureClass c) { return c == FeatureClass::kGeneral || c == FeatureClass::kLayered; }

FeatureClass ChooseFeatureClass(uint32_t effects);
// The class that runs without --specialize: the general one, or the layered one where the
// scene needs it.
FeatureClass UnspecializedFeatureClass(uint32_t effects);
const char* FeatureClassName(FeatureClass c);

}  // namespace pt
