// A glTF material at a surface point with its extensions resolved (textures applied): what the
// layered shade variant passes to the BSDF (src/materials/gltf_layered.h). The core fields are
// the Material's; the extension parameters follow. Directions (the clearcoat normal, the
// anisotropy direction) are resolved in world space and moved into the shading frame by
// LocalizeLayers once the shade stage has built its frame.
#pragma once

#include "src/scene/material_extension.h"
#include "src/scene/scene_types.h"

namespace pt {

struct GltfLayers {
  uint32_t mask = 0;  // GltfExtensionBit: the extensions present
  float specular = 1.0f;
  vec3 specularColor = vec3(1.0f);
  float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
  vec3 coatNormal = vec3(0.0f, 0.0f, 1.0f);  // unit; world, then local
  vec3 sheenColor = vec3(0.0f);
  float sheenRoughness = 0.0f;
  float iridescence = 0.0f, iridescenceIor = 1.3f, thickness = 400.0f;  // thickness in nm
  float anisotropy = 0.0f;
  vec3 anisotropyDir = vec3(1.0f, 0.0f, 0.0f);  // unit tangent; world, then local (z = 0)
  float diffuseTransmission = 0.0f;
  vec3 diffuseTransmissionColor = vec3(1.0f);
};

struct LayeredMaterial : Material {
  GltfLayers layers;
};

PT_HDI LayeredMaterial MakeLayered(const Material& m) {
  LayeredMaterial l;
  static_cast<Material&>(l) = m;
  return l;
}

// Whether the glTF BSDF needs the layered code: extensions, unlit, or energy compensation.
PT_HDI bool UsesLayers(const Material& m) {
  return m.ext >= 0 || (m.flags & (kMaterialUnlit | kMaterialEnergyCompensation)) != 0;
}

// The world-space directions into the shading frame f (whose z is the shading normal).
PT_HDI void LocalizeLayers(const Frame& f, LayeredMaterial* m) {
  GltfLayers& x = m->layers;
  if (x.mask & kExtClearcoat) {
    vec3 n = f.ToLocal(x.coatNormal);
    float len2 = glm::dot(n, n);
    x.coatNormal = len2 > 0.0f ? n / sqrtf(len2) : vec3(0.0f, 0.0f, 1.0f);
  }
  if (x.mask & kExtAnisotropy) {
    vec3 d = f.ToLocal(x.anisotropyDir);
    float len2 = d.x * d.x + d.y * d.y;
    x.anisotropyDir = len2 > 0.0f ? vec3(d.x, d.y, 0.0f) / sqrtf(len2) : vec3(1.0f, 0.0f, 0.0f);
  }
}

}  // namespace pt
