// Software texture lookup shared by both backends: bilinear filtering of linear RGB texels
// (sRGB decoded at load) with glTF's wrap modes. No hardware texture units, so the CPU and
// GPU compute the same values.
#pragma once

#include "src/geometry/interaction.h"
#include "src/scene/scene_view.h"

namespace pt {

// Maps an integer texel coordinate into [0, size) by the wrap mode.
PT_HDI int WrapTexel(int i, int size, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::kClampToEdge: return i < 0 ? 0 : (i >= size ? size - 1 : i);
    case TextureWrap::kMirroredRepeat: {
      int period = 2 * size;
      int m = ((i % period) + period) % period;
      return m < size ? m : period - 1 - m;
    }
    case TextureWrap::kRepeat:
    default: return ((i % size) + size) % size;
  }
}

// Bilinear lookup at texture coordinates uv (glTF: u right, v down, texel centres at +0.5).
PT_HDI vec3 SampleTexture(const SceneView& s, int32_t textureIndex, vec2 uv) {
  const Texture& t = s.textures[textureIndex];
  float x = uv.x * float(t.width) - 0.5f;
  float y = uv.y * float(t.height) - 0.5f;
  // Reduce large coordinates first so float precision survives repeat wrapping.
  x -= floorf(x / float(t.width)) * float(t.width) * (t.wrapS == TextureWrap::kRepeat);
  y -= floorf(y / float(t.height)) * float(t.height) * (t.wrapT == TextureWrap::kRepeat);
  float fx = floorf(x), fy = floorf(y);
  float ax = x - fx, ay = y - fy;
  int x0 = int(fx), y0 = int(fy);
  int w = int(t.width), h = int(t.height);
  int xs[2] = {WrapTexel(x0, w, t.wrapS), WrapTexel(x0 + 1, w, t.wrapS)};
  int ys[2] = {WrapTexel(y0, h, t.wrapT), WrapTexel(y0 + 1, h, t.wrapT)};
  const vec3* texels = s.texels + t.offset;
  vec3 top = (1.0f - ax) * texels[ys[0] * w + xs[0]] + ax * texels[ys[0] * w + xs[1]];
  vec3 bottom = (1.0f - ax) * texels[ys[1] * w + xs[0]] + ax * texels[ys[1] * w + xs[1]];
  return (1.0f - ay) * top + ay * bottom;
}

// The material at a surface point: textures applied to a copy of the material's constants.
PT_HDI Material ResolveMaterial(const SceneView& s, const SurfaceInteraction& si) {
  Material m = s.materials[si.material];
  if (m.baseColorTexture >= 0) m.albedo *= SampleTexture(s, m.baseColorTexture, si.texUv);
  return m;
}

}  // namespace pt
