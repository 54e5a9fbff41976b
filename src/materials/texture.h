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

// A continuous texel coordinate brought into a small range that selects the same texels and
// weights: exact remainders (fmodf) by the wrap's period, so any finite coordinate converts to
// int without overflow. Clamping to [-1, size] changes nothing either: past the edges both
// taps read the edge texel. A NaN or infinite coordinate reads as 0.
PT_HDI float ReduceTexelCoordinate(float x, int size, TextureWrap wrap) {
  if (!(fabsf(x) <= 3.0e38f)) return 0.0f;
  float s = float(size);
  if (wrap == TextureWrap::kClampToEdge) return fminf(fmaxf(x, -1.0f), s);
  float period = wrap == TextureWrap::kMirroredRepeat ? 2.0f * s : s;
  float r = fmodf(x, period);  // exact, |r| < period, sign of x
  return r < 0.0f ? r + period : r;
}

// Bilinear lookup at texture coordinates uv (glTF: u right, v down from the image's first row,
// texel centres at +0.5), wrap modes per axis.
PT_HDI vec3 SampleTexture(const SceneView& s, int32_t textureIndex, vec2 uv) {
  const Texture& t = s.textures[textureIndex];
  int w = int(t.width), h = int(t.height);
  float x = ReduceTexelCoordinate(uv.x * float(w) - 0.5f, w, t.wrapS);
  float y = ReduceTexelCoordinate(uv.y * float(h) - 0.5f, h, t.wrapT);
  float fx = floorf(x), fy = floorf(y);
  float ax = x - fx, ay = y - fy;
  int x0 = int(fx), y0 = int(fy);
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
