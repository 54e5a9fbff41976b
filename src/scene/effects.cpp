#include "src/scene/effects.h"

#include "src/materials/bsdf.h"

namespace pt {
namespace {

// The layered variant's effects of one used material: its extensions, unlit, compensation.
uint32_t LayeredEffects(const SceneDesc& d, const Material& m) {
  uint32_t e = 0;
  if (m.type == MaterialType::kGltfPbr && (m.flags & kMaterialUnlit)) e |= kEffectUnlit;
  bool metal = m.type == MaterialType::kConductor ||
               (m.type == MaterialType::kGltfPbr && m.metallic > 0.0f);
  if ((m.flags & kMaterialEnergyCompensation) && metal) e |= kEffectEnergyCompensation;
  if (m.type != MaterialType::kGltfPbr || m.ext < 0 || size_t(m.ext) >= d.materialExtensions.size())
    return e;
  const uint32_t kBitEffect[] = {kEffectSpecular,    kEffectClearcoat, kEffectSheen,
                                 kEffectIridescence, kEffectAnisotropy, kEffectDiffuseTransmission};
  uint32_t mask = d.materialExtensions[size_t(m.ext)].mask;
  for (int bit = 0; bit < 6; ++bit)
    if (mask & (1u << bit)) e |= kBitEffect[bit];
  return e;
}

}  // namespace

uint32_t AnalyzeEffects(const Scene& scene) {
  const SceneDesc& d = scene.desc;
  std::vector<bool> used(d.materials.size(), false);
  for (const PrimRef& prim : scene.prims)
    if (prim.material < used.size()) used[prim.material] = true;
  for (const InstanceDesc& inst : d.instances)  // an override is a material the scene shows
    if (inst.material >= 0 && size_t(inst.material) < used.size()) used[inst.material] = true;
  uint32_t e = 0;
  const uint32_t kTypeEffect[] = {kEffectDiffuse,    kEffectEmissive, kEffectConductor,
                                  kEffectDielectric, kEffectPlastic,  kEffectGltfPbr};
  static_assert(sizeof(kTypeEffect) / sizeof(kTypeEffect[0]) == size_t(MaterialType::kCount));
  for (size_t i = 0; i < d.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = d.materials[i];
    e |= kTypeEffect[size_t(m.type)];
    bool glass = m.type == MaterialType::kDielectric ||
                 (m.type == MaterialType::kGltfPbr && m.transmission > 0.0f);
    if (glass && MaxComponent(m.absorption) > 0.0f) e |= kEffectAbsorption;
    bool glossy = m.type == MaterialType::kConductor || m.type == MaterialType::kDielectric ||
                  m.type == MaterialType::kPlastic || m.type == MaterialType::kGltfPbr;
    if (glossy && !IsSmooth(m)) e |= kEffectRoughLobes;
    for (int32_t t : {m.baseColorTexture, m.metallicRoughnessTexture, m.normalTexture,
                      m.emissiveTexture, m.transmissionTexture})
      if (t >= 0) e |= kEffectTextures;
    if (m.normalTexture >= 0) e |= kEffectNormalMaps;
    if (m.emissiveTexture >= 0 && !IsBlack(m.radiance)) e |= kEffectEmissiveTextures;
    if (m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) e |= kEffectAlpha;
    if (m.flags & kMaterialCullBack) e |= kEffectBackfaceCulling;
    if (m.type == MaterialType::kGltfPbr && m.transmission > 0.0f) e |= kEffectTransmission;
    e |= LayeredEffects(d, m);
  }
  for (const Light& l : scene.lights) {
    if (l.type == LightType::kArea) e |= kEffectAreaLights;
    if (l.type == LightType::kPoint) e |= kEffectPointLights;
    if (l.type == LightType::kBackground) e |= kEffectBackgroundLight;
    if (l.type == LightType::kDirectional) e |= kEffectDirectionalLights;
    if (l.type == LightType::kSpot) e |= kEffectSpotLights;
  }
  // The map's code runs whenever there is a map, even a dark one the camera sees.
  if (d.environment.HasMap()) e |= kEffectEnvironmentMap;
  if (!d.directionalLights.empty()) e |= kEffectDirectionalLights;
  if (!d.pointLights.empty()) e |= kEffectPointLights;
  if (!d.spotLights.empty()) e |= kEffectSpotLights;
  if (d.camera.apertureRadius > 0.0f) e |= kEffectDepthOfField;
  if (d.media.Active()) e |= kEffectMedia;
  return e;
}

std::vector<std::string> EffectNames(uint32_t effects) {
  static const char* kNames[] = {"diffuse",      "emissive",        "conductor",
                                 "dielectric",   "plastic",         "absorption",
                                 "rough_lobes",  "textures",        "depth_of_field",
                                 "area_lights",  "point_lights",    "background_light",
                                 "directional_lights", "environment_map",
                                 "gltf_pbr",     "normal_maps",     "alpha",
                                 "transmission", "emissive_textures", "backface_culling",
                                 "spot_lights",  "specular",        "clearcoat",
                                 "sheen",        "iridescence",     "anisotropy",
                                 "diffuse_transmission", "unlit",   "energy_compensation",
                                 "media"};
  std::vector<std::string> names;
  for (uint32_t bit = 0; bit < sizeof(kNames) / sizeof(kNames[0]); ++bit)
    if (effects & (1u << bit)) names.push_back(kNames[bit]);
  return names;
}

FeatureClass ChooseFeatureClass(uint32_t effects) {
  if (effects & kLayeredEffects) return FeatureClass::kLayered;
  const uint32_t kDiffuseOnly = kEffectDiffuse | kEffectEmissive;
  // The glTF material, normal maps and emissive textures run only in the general variant;
  // alpha and culling are the intersector's (no variant), transmission implies glTF.
  const uint32_t kNeedsGeneral = kEffectPlastic | kEffectRoughLobes | kEffectTextures |
                                 kEffectGltfPbr | kEffectNormalMaps | kEffectEmissiveTextures |
                                 kEffectTransmission;
  uint32_t materials = effects & (kDiffuseOnly | kEffectConductor | kEffectDielectric |
                                  kEffectAbsorption | kNeedsGeneral);
  if ((materials & ~kDiffuseOnly) == 0) return FeatureClass::kDiffuse;
  if ((materials & kNeedsGeneral) == 0) return FeatureClass::kSmooth;
  return FeatureClass::kGeneral;
}

FeatureClass UnspecializedFeatureClass(uint32_t effects) {
  return (effects & kLayeredEffects) ? FeatureClass::kLayered : FeatureClass::kGeneral;
}

const char* FeatureClassName(FeatureClass c) {
  switch (c) {
    case FeatureClass::kDiffuse: return "diffuse";
    case FeatureClass::kSmooth: return "smooth";
    case FeatureClass::kLayered: return "layered";
    default: return "general";
  }
}

}  // namespace pt
