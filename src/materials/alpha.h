// The hit test that IntersectPrim runs, after a geometric hit, on primitives whose PrimRef has
// kHitTestBit: glTF alpha (MASK: kept where alpha >= alphaCutoff; BLEND: kept with probability
// alpha, stochastic opacity) and back-face culling of single-sided opaque materials. Every
// traversal (closest hit for camera and extension rays, any hit for shadow rays) calls
// IntersectPrim, so all of them see the same surface.
//
// BLEND's coin is a hash of the ray (origin and direction bits) and the primitive's shape
// index: the same ray meets the same decision whichever traversal asks and in whatever order
// primitives are tested, a render is reproducible, and both backends decide alike. Distinct
// rays (every sample's rays differ) get independent coins, so the expected image is alpha
// times the surface plus (1 - alpha) times what lies behind it.
//
// alpha = baseColorFactor.a x baseColorTexture.a x COLOR_0.a, the texture read at level 0 (a
// traversal knows no footprint; the cutoff then follows the texture's own texels).
#pragma once

#include <cstring>

#include "src/core/ray.h"
#include "src/core/rng.h"
#include "src/materials/surface_attributes.h"

namespace pt {

PT_HDI uint32_t FloatBits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof(u));
  return u;
}

// A uniform number in [0, 1) that depends only on the ray and the shape.
PT_HDI float HitCoin(const Ray& ray, uint32_t shape) {
  glm::uvec4 h = Pcg4d(glm::uvec4(FloatBits(ray.o.x) ^ FloatBits(ray.d.y),
                                  FloatBits(ray.o.y) ^ FloatBits(ray.d.z),
                                  FloatBits(ray.o.z) ^ FloatBits(ray.d.x), shape));
  return BitsToUnitFloat(Pcg4d(h).x);
}

// glTF alpha of a material at shape parameters param of a primitive.
PT_HDI float MaterialAlphaAt(const SceneView& s, const Material& m, PrimRef ref, vec2 param) {
  float alpha = m.alpha * VertexColorAt(s, ref, param).w;
  if (m.baseColorTexture >= 0)
    alpha *= SampleTextureRef(s, m.baseColorTexture, TexCoordsAt(s, ref, param, 0.0f)).w;
  return alpha;
}

// Whether the front of a triangle or quad faces away from the ray.
PT_HDI bool HitsBackFace(const SceneView& s, PrimRef ref, vec3 d) {
  vec3 n;
  if (ref.Type() == ShapeType::kTriangle) {
    const Triangle& t = s.triangles[ref.Index()];
    n = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
  } else if (ref.Type() == ShapeType::kQuad) {
    const Quad& q = s.quads[ref.Index()];
    n = glm::cross(q.u, q.v);
  } else {
    return false;  // spheres are never culled
  }
  return glm::dot(n, d) > 0.0f;
}

// Whether a geometric hit at shape parameters param of ref (which has kHitTestBit) counts.
PT_HDI bool AcceptHit(const SceneView& s, PrimRef ref, const Ray& ray, vec2 param) {
  const Material& m = s.materials[ref.material];
  if ((m.flags & kMaterialCullBack) && HitsBackFace(s, ref, ray.d)) return false;
  if (!(m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend))) return true;
  float alpha = MaterialAlphaAt(s, m, ref, param);
  if (m.flags & kMaterialAlphaMask) return alpha >= m.alphaCutoff;
  return HitCoin(ray, ref.tagIndex & ~PrimRef::kHitTestBit) < alpha;
}

}  // namespace pt
