// The glTF material extensions beyond the core material (KHR_materials_specular, _clearcoat,
// _sheen, _iridescence, _anisotropy, _diffuse_transmission) as one device array: a Material
// with extensions names its entry (Material::ext), so materials without them read nothing more
// than the core. Factors as the extensions define them; texture slots index the scene's
// TextureRefs (-1: none), each read through the channel noted (docs/gltf-materials.md).
#pragma once

#include "src/core/math.h"

namespace pt {

// Bits of GltfMaterialExtension::mask: which extensions the material has (with an effect).
enum GltfExtensionBit : uint32_t {
  kExtSpecular = 1u << 0,
  kExtClearcoat = 1u << 1,
  kExtSheen = 1u << 2,
  kExtIridescence = 1u << 3,
  kExtAnisotropy = 1u << 4,
  kExtDiffuseTransmission = 1u << 5,
};

struct GltfMaterialExtension {
  uint32_t mask = 0;
  // KHR_materials_specular: dielectric F0 = min(F0(ior) specularColor, 1) specular, F90 = specular.
  float specular = 1.0f;
  vec3 specularColor = vec3(1.0f);
  int32_t specularTexture = -1;       // A
  int32_t specularColorTexture = -1;  // RGB (sRGB)
  // KHR_materials_clearcoat: a GGX coat of ior 1.5 with its own roughness and normal.
  float clearcoat = 0.0f;
  float clearcoatRoughness = 0.0f;
  float clearcoatNormalScale = 1.0f;
  int32_t clearcoatTexture = -1;           // R
  int32_t clearcoatRoughnessTexture = -1;  // G
  int32_t clearcoatNormalTexture = -1;     // tangent-space normal
  // KHR_materials_sheen.
  vec3 sheenColor = vec3(0.0f);
  float sheenRoughness = 0.0f;
  int32_t sheenColorTexture = -1;      // RGB (sRGB)
  int32_t sheenRoughnessTexture = -1;  // A
  // KHR_materials_iridescence: thickness = mix(min, max, texture G) nm (max without texture).
  float iridescence = 0.0f;
  float iridescenceIor = 1.3f;
  float thicknessMin = 100.0f, thicknessMax = 400.0f;
  int32_t iridescenceTexture = -1;           // R
  int32_t iridescenceThicknessTexture = -1;  // G
  // KHR_materials_anisotropy: strength and the rotation (radians) from the tangent.
  float anisotropy = 0.0f;
  float anisotropyRotation = 0.0f;
  int32_t anisotropyTexture = -1;  // RG direction in [-1, 1], B strength
  // KHR_materials_diffuse_transmission.
  float diffuseTransmission = 0.0f;
  vec3 diffuseTransmissionColor = vec3(1.0f);
  int32_t diffuseTransmissionTexture = -1;       // A
  int32_t diffuseTransmissionColorTexture = -1;  // RGB (sRGB)
};

}  // namespace pt
