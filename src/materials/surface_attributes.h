// Per-vertex attributes at a point of a primitive, for materials: texture coordinates (both
// UV sets) with the footprint that picks a mip level, COLOR_0, and the tangent frame of
// normal textures. Shared by shading, the alpha test inside traversal and light sampling, so
// each computes the same value at the same point.
//
// Footprint (the filter width that chooses a mip level): the width a camera pixel covers at
// the point, spread * distance from the camera / sqrt(|cos|) with cos between the geometric
// normal and the view from the camera (the geometric mean of the footprint's two axes, so a
// grazing view neither aliases along its short axis nor blurs fully along its long one). It is
// pbrt-v4's Approximate_dp_dxy idea: every hit, primary or not, is filtered as the camera
// would see it, so it needs no per-path state, and emission looked up by next-event estimation
// and by a BSDF-sampled hit is the same function of the point (MIS stays consistent). The
// width in a UV set is the world width times sqrt(uv area / world area) of the triangle.
#pragma once

#include "src/core/ray.h"
#include "src/materials/texture.h"

namespace pt {

// The fraction of a pixel's width that a texture lookup prefilters over, for a render that
// takes `spp` samples in each pixel: 1 / sqrt(spp), at least 1/8 (pbrt-v4's scaling of ray
// differentials). The samples of a pixel spread over it on a grid about 1 / sqrt(spp) wide, so
// each needs to average only its share: a 1-spp preview filters over the whole pixel (no
// aliasing), a converged render (64 spp and more) keeps detail down to an eighth of a pixel.
// It is a render parameter (the camera's textureFootprint, set once on the host from the
// render's target spp), so both backends, every chunk and every resumed run filter alike.
PT_HDI float TextureFootprintScale(int spp) {
  return spp <= 1 ? 1.0f : fmaxf(0.125f, 1.0f / sqrtf(float(spp)));
}

// World-space filter width at p (geometric normal ng) for the camera's pixel spread.
PT_HDI float FootprintWidth(const Camera& cam, vec3 p, vec3 ng) {
  vec3 d = p - cam.position;
  float dist = glm::length(d);
  if (!(dist > 0.0f)) return 0.0f;
  float cosView = fabsf(glm::dot(ng, d)) / dist;
  return cam.textureFootprint * cam.pixelSpread * dist / sqrtf(fmaxf(cosView, 1e-2f));
}

namespace detail {

// sqrt(uv area / world area) of a triangle: UV units per world unit.
PT_HDI float UvDensity(vec2 a, vec2 b, vec2 c, float worldArea2) {
  vec2 e1 = b - a, e2 = c - a;
  float uvArea2 = fabsf(e1.x * e2.y - e1.y * e2.x);
  return worldArea2 > 0.0f ? sqrtf(uvArea2 / worldArea2) : 0.0f;
}

PT_HDI vec2 Interpolate(vec2 a, vec2 b, vec2 c, vec2 bary) {
  return (1.0f - bary.x - bary.y) * a + bary.x * b + bary.y * c;
}

}  // namespace detail

// Texture coordinates of the point with shape parameters `param` (triangle barycentrics
// (b1, b2), quad (s, t), sphere (phi, theta) / (2 pi, pi)) on primitive ref, and their
// footprints for a world filter width (0: level 0 only). Without TEXCOORD_n a triangle reads
// its barycentrics and quads and spheres their parameters, in both sets.
PT_HDI TexCoords TexCoordsAt(const SceneView& s, PrimRef ref, vec2 param, float worldWidth) {
  TexCoords tc;
  tc.uv[0] = tc.uv[1] = param;
  tc.width[0] = tc.width[1] = 0.0f;
  switch (ref.Type()) {
    case ShapeType::kTriangle: {
      const Triangle& tri = s.triangles[ref.Index()];
      float area2 = glm::length(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
      const TriangleUvs* sets[2] = {s.triangleUvs, s.triangleUvs1 ? s.triangleUvs1 : s.triangleUvs};
      for (int k = 0; k < 2; ++k) {
        if (sets[k] == nullptr) {
          tc.width[k] = worldWidth * detail::UvDensity(vec2(0, 0), vec2(1, 0), vec2(0, 1), area2);
          continue;
        }
        const TriangleUvs& t = sets[k][ref.Index()];
        tc.uv[k] = detail::Interpolate(t.uv0, t.uv1, t.uv2, param);
        tc.width[k] = worldWidth * detail::UvDensity(t.uv0, t.uv1, t.uv2, area2);
      }
      break;
    }
    case ShapeType::kQuad: {
      const Quad& q = s.quads[ref.Index()];
      tc.width[0] = tc.width[1] = worldWidth / sqrtf(glm::length(glm::cross(q.u, q.v)));
      break;
    }
    default: {
      float r = s.spheres[ref.Index()].radius;
      tc.width[0] = tc.width[1] = worldWidth / (2.0f * sqrtf(kPi) * r);
      break;
    }
  }
  return tc;
}

// COLOR_0 (linear RGBA) at barycentrics bary of a triangle; white elsewhere.
PT_HDI vec4 VertexColorAt(const SceneView& s, PrimRef ref, vec2 bary) {
  if (s.triangleColors == nullptr || ref.Type() != ShapeType::kTriangle) return vec4(1.0f);
  const TriangleColors& c = s.triangleColors[ref.Index()];
  return (1.0f - bary.x - bary.y) * c.c0 + bary.x * c.c1 + bary.y * c.c2;
}

// The tangent-space basis (t, b) of a normal texture read through UV set `set` at a triangle
// point with unit shading normal n, orthonormal to n. With glTF TANGENT data: the interpolated
// tangent and its sign w, b = w cross(n, t). Without: per-triangle tangents from the UV
// derivatives (t along dp/du; b = w cross(n, t) with w chosen so b points along -dp/dv, image
// up, as glTF's normal maps expect), the flat-per-triangle special case of MikkTSpace. False
// when no frame exists (degenerate UVs, not a triangle).
PT_HDI bool TangentFrameAt(const SceneView& s, PrimRef ref, vec2 bary, uint32_t set, vec3 n,
                           vec3* t, vec3* b) {
  if (ref.Type() != ShapeType::kTriangle) return false;
  vec3 tangent;
  float sign;
  if (s.triangleTangents != nullptr) {
    const TriangleTangents& tt = s.triangleTangents[ref.Index()];
    vec4 v = (1.0f - bary.x - bary.y) * tt.t0 + bary.x * tt.t1 + bary.y * tt.t2;
    tangent = vec3(v);
    sign = v.w < 0.0f ? -1.0f : 1.0f;
  } else {
    const TriangleUvs* uvs = set != 0 && s.triangleUvs1 ? s.triangleUvs1 : s.triangleUvs;
    if (uvs == nullptr) return false;
    const Triangle& tri = s.triangles[ref.Index()];
    const TriangleUvs& uv = uvs[ref.Index()];
    vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
    vec2 d1 = uv.uv1 - uv.uv0, d2 = uv.uv2 - uv.uv0;
    float det = d1.x * d2.y - d1.y * d2.x;
    if (det == 0.0f) return false;
    vec3 dpdu = (d2.y * e1 - d1.y * e2) / det;
    vec3 dpdv = (d1.x * e2 - d2.x * e1) / det;
    tangent = dpdu;
    sign = glm::dot(glm::cross(n, dpdu), dpdv) > 0.0f ? -1.0f : 1.0f;
  }
  tangent -= glm::dot(tangent, n) * n;  // Gram-Schmidt against the shading normal
  float len2 = glm::dot(tangent, tangent);
  if (!(len2 > 0.0f && len2 < kInfinity)) return false;
  *t = tangent / sqrtf(len2);
  *b = sign * glm::cross(n, *t);
  return true;
}

}  // namespace pt
