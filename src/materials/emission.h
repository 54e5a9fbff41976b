// Emitted radiance of an area light at a point of its primitive, for next-event estimation:
// the light's constant radiance, times the glTF emissive texture there when the material has
// one. The texture is read with the footprint a hit at that point uses (surface_attributes.h),
// so light sampling and BSDF-sampled hits see one emission function and MIS stays unbiased.
#pragma once

#include "src/materials/surface_attributes.h"

namespace pt {

// param: the point's shape parameters (triangle (b1, b2), quad (s, t)); p, n its position and
// unit geometric normal.
PT_HDI vec3 AreaLightRadiance(const SceneView& s, const Light& light, vec2 param, vec3 p,
                              vec3 n) {
  PrimRef prim = s.prims[light.prim];
  const Material& m = s.materials[prim.material];
  if (m.type != MaterialType::kGltfPbr || m.emissiveTexture < 0) return light.radiance;
  TexCoords tc = TexCoordsAt(s, prim, param, FootprintWidth(s.camera, p, n));
  return light.radiance * vec3(SampleTextureRef(s, m.emissiveTexture, tc));
}

}  // namespace pt
