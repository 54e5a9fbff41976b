// Emitted radiance of an area light at a point of its primitive, for next-event estimation:
// the light's constant radiance, times the glTF emissive texture there when the material has
// one. The texture is read with the footprint a hit at that point uses (surface_attributes.h),
// so light sampling and BSDF-sampled hits see one emission function and MIS stays unbiased.
// An alpha-tested emitter emits what a ray would find there: nothing where MASK cuts it out,
// alpha times its emission under BLEND (a ray meets it with probability alpha).
#pragma once

#include "src/materials/alpha.h"
#include "src/materials/surface_attributes.h"

namespace pt {

// param: the point's shape parameters (triangle (b1, b2), quad (s, t)); p, n its position and
// unit geometric normal.
PT_HDI vec3 AreaLightRadiance(const SceneView& s, const Light& light, vec2 param, vec3 p,
                              vec3 n) {
  PrimRef prim = s.prims[light.prim];
  const Material& m = s.materials[prim.material];
  if (m.type != MaterialType::kGltfPbr) return light.radiance;
  vec3 le = light.radiance;
  if (m.emissiveTexture >= 0) {
    TexCoords tc = TexCoordsAt(s, prim, param, FootprintWidth(s.camera, p, n));
    le *= vec3(SampleTextureRef(s, m.emissiveTexture, tc));
  }
  if (m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend)) {
    float alpha = MaterialAlphaAt(s, m, prim, param);
    le *= (m.flags & kMaterialAlphaMask) ? (alpha >= m.alphaCutoff ? 1.0f : 0.0f) : alpha;
  }
  return le;
}

}  // namespace pt
