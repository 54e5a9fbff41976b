#include "src/lights/emission_power.h"

#include <algorithm>
#include <cmath>

#include "src/core/sampling.h"
#include "src/materials/surface_attributes.h"

namespace pt {

namespace {

// The old estimate, for quads, spheres and triangles without UVs: 16 stratified points, each
// read at the mip level whose footprint is a sixteenth of the primitive.
vec3 StratifiedMean(const SceneView& view, const PrimRef& prim, int32_t textureRef, float area) {
  constexpr int kGrid = 4;
  float width = std::sqrt(area / float(kGrid * kGrid));
  vec3 sum(0.0f);
  for (int i = 0; i < kGrid * kGrid; ++i) {
    vec2 u((float(i % kGrid) + 0.5f) / kGrid, (float(i / kGrid) + 0.5f) / kGrid);
    vec2 param = u;  // quads: (s, t)
    if (prim.Type() == ShapeType::kTriangle) {
      vec2 b = SampleUniformTriangle(u);
      param = vec2(b.y, 1.0f - b.x - b.y);
    }
    sum += vec3(SampleTextureRef(view, textureRef, TexCoordsAt(view, prim, param, width)));
  }
  return sum / float(kGrid * kGrid);
}

float EmitterArea(const SceneView& view, const PrimRef& prim) {
  switch (prim.Type()) {
    case ShapeType::kQuad: {
      const Quad& q = view.quads[prim.Index()];
      return glm::length(glm::cross(q.u, q.v));
    }
    case ShapeType::kTriangle: {
      const Triangle& t = view.triangles[prim.Index()];
      return 0.5f * glm::length(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
    }
    case ShapeType::kSphere: {
      float r = view.spheres[prim.Index()].radius;
      return 4.0f * kPi * r * r;
    }
  }
  return 0.0f;
}

// Twice the signed area of (a, b, p): which side of edge ab the point p lies on.
double EdgeSide(glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
  return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// The mean over the texel centres the UV triangle covers (see the header).
vec3 TexelMean(const SceneView& view, const TextureRef& ref, const TriangleUvs& uvs) {
  const Texture& tex = view.textures[ref.texture];
  glm::dvec2 p[3];
  const vec2 in[3] = {uvs.uv0, uvs.uv1, uvs.uv2};
  for (int k = 0; k < 3; ++k) {
    vec3 uv1(in[k], 1.0f);
    p[k] = glm::dvec2(glm::dot(ref.row0, uv1), glm::dot(ref.row1, uv1));  // texture transform
  }
  glm::dvec2 lo = glm::min(p[0], glm::min(p[1], p[2])), hi = glm::max(p[0], glm::max(p[1], p[2]));
  if (!std::isfinite(lo.x + lo.y + hi.x + hi.y)) return vec3(0.0f);
  int last = int(tex.levels) - 1, level = 0;
  TextureLevel l = LevelOf(tex, 0);
  auto boxTexels = [&](const TextureLevel& at) {
    return (hi.x - lo.x) * at.width * (hi.y - lo.y) * at.height;
  };
  while (level < last && boxTexels(l) > kEmissionTexelBudget) l = LevelOf(tex, ++level);
  // A box still too large at the last level wraps a repeating texture many times: the whole
  // texture's mean (the last level's texel, or the mean of that level).
  if (boxTexels(l) > 4.0 * kEmissionTexelBudget) {
    vec3 sum(0.0f);
    for (int i = 0; i < l.width * l.height; ++i)
      sum += vec3(DecodeTexel(view.texels[l.offset + uint32_t(i)], tex.srgb != 0));
    return sum / float(l.width * l.height);
  }
  double orientation = EdgeSide(p[0], p[1], p[2]) < 0.0 ? -1.0 : 1.0;
  int i0 = int(std::floor(lo.x * l.width - 0.5)), i1 = int(std::ceil(hi.x * l.width - 0.5));
  int j0 = int(std::floor(lo.y * l.height - 0.5)), j1 = int(std::ceil(hi.y * l.height - 0.5));
  glm::dvec3 sum(0.0);
  int count = 0;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      glm::dvec2 c((i + 0.5) / l.width, (j + 0.5) / l.height);
      if (orientation * EdgeSide(p[0], p[1], c) < 0.0 ||
          orientation * EdgeSide(p[1], p[2], c) < 0.0 ||
          orientation * EdgeSide(p[2], p[0], c) < 0.0)
        continue;
      int x = WrapTexel(i, l.width, tex.wrapS), y = WrapTexel(j, l.height, tex.wrapT);
      sum += glm::dvec3(vec3(DecodeTexel(view.texels[l.offset + uint32_t(y * l.width + x)],
                                         tex.srgb != 0)));
      ++count;
    }
  }
  if (count > 0) return vec3(sum / double(count));
  glm::dvec2 centroid = (p[0] + p[1] + p[2]) / 3.0;
  return vec3(SampleLevel(view, tex, level, vec2(centroid)));
}

}  // namespace

vec3 MeanEmissiveTexture(const SceneView& view, const PrimRef& prim) {
  const Material& m = view.materials[prim.material];
  if (m.type != MaterialType::kGltfPbr || m.emissiveTexture < 0) return vec3(1.0f);
  const TextureRef& ref = view.textureRefs[m.emissiveTexture];
  const TriangleUvs* set = ref.texCoord != 0 && view.triangleUvs1 ? view.triangleUvs1
                                                                  : view.triangleUvs;
  if (prim.Type() == ShapeType::kTriangle && set != nullptr)
    return TexelMean(view, ref, set[prim.Index()]);
  return StratifiedMean(view, prim, m.emissiveTexture, EmitterArea(view, prim));
}

}  // namespace pt
