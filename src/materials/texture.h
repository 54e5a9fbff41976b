// Software texture lookup shared by both backends: RGBA8 texels (sRGB decoded per tap through
// one table), glTF's wrap modes, bilinear taps on a level, and trilinear filtering between the
// two levels of a mip pyramid that bracket the footprint (Williams 1983). No hardware texture
// units, so the CPU and GPU compute the same values.
#pragma once

#include "src/materials/srgb_table.h"
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

// One packed texel (R | G << 8 | B << 16 | A << 24) as linear RGBA.
PT_HDI vec4 DecodeTexel(uint32_t packed, bool srgb) {
  uint32_t r = packed & 0xffu, g = (packed >> 8) & 0xffu, b = (packed >> 16) & 0xffu;
  float a = float(packed >> 24) / 255.0f;
  if (srgb) return vec4(SrgbCodeToLinear(r), SrgbCodeToLinear(g), SrgbCodeToLinear(b), a);
  return vec4(float(r) / 255.0f, float(g) / 255.0f, float(b) / 255.0f, a);
}

// Where mip level `level` of a texture lives: each level halves the previous (rounded down,
// at least 1 texel) and follows it in the texel array.
struct TextureLevel {
  int width, height;
  uint32_t offset;
};

PT_HDI TextureLevel LevelOf(const Texture& t, int level) {
  TextureLevel l{int(t.width), int(t.height), t.offset};
  for (int i = 0; i < level; ++i) {
    l.offset += uint32_t(l.width) * uint32_t(l.height);
    l.width = l.width > 1 ? l.width / 2 : 1;
    l.height = l.height > 1 ? l.height / 2 : 1;
  }
  return l;
}

// Texels a pyramid of width x height occupies (what the loader allocates).
PT_HDI uint64_t PyramidTexelCount(uint32_t width, uint32_t height, uint32_t* levels) {
  uint64_t count = 0;
  uint32_t n = 0;
  while (true) {
    count += uint64_t(width) * height;
    ++n;
    if (width == 1 && height == 1) break;
    width = width > 1 ? width / 2 : 1;
    height = height > 1 ? height / 2 : 1;
  }
  if (levels) *levels = n;
  return count;
}

// Bilinear lookup on one level at texture coordinates uv (glTF: u right, v down from the
// image's first row, texel centres at +0.5), wrap modes per axis.
PT_HDI vec4 SampleLevel(const SceneView& s, const Texture& t, int level, vec2 uv) {
  TextureLevel l = LevelOf(t, level);
  int w = l.width, h = l.height;
  float x = ReduceTexelCoordinate(uv.x * float(w) - 0.5f, w, t.wrapS);
  float y = ReduceTexelCoordinate(uv.y * float(h) - 0.5f, h, t.wrapT);
  float fx = floorf(x), fy = floorf(y);
  float ax = x - fx, ay = y - fy;
  int x0 = int(fx), y0 = int(fy);
  int xs[2] = {WrapTexel(x0, w, t.wrapS), WrapTexel(x0 + 1, w, t.wrapS)};
  int ys[2] = {WrapTexel(y0, h, t.wrapT), WrapTexel(y0 + 1, h, t.wrapT)};
  const uint32_t* texels = s.texels + l.offset;
  bool srgb = t.srgb != 0;
  vec4 top = (1.0f - ax) * DecodeTexel(texels[ys[0] * w + xs[0]], srgb) +
             ax * DecodeTexel(texels[ys[0] * w + xs[1]], srgb);
  vec4 bottom = (1.0f - ax) * DecodeTexel(texels[ys[1] * w + xs[0]], srgb) +
                ax * DecodeTexel(texels[ys[1] * w + xs[1]], srgb);
  return (1.0f - ay) * top + ay * bottom;
}

// Trilinear lookup: lod is log2 of the footprint in level-0 texels; lod <= 0 (magnification)
// is a bilinear lookup of level 0, lod past the last level reads the 1 x 1 level.
PT_HDI vec4 SampleTexture(const SceneView& s, int32_t textureIndex, vec2 uv, float lod = 0.0f) {
  const Texture& t = s.textures[textureIndex];
  int last = int(t.levels) - 1;
  if (!(lod > 0.0f) || last == 0) return SampleLevel(s, t, 0, uv);
  if (lod >= float(last)) return SampleLevel(s, t, last, uv);
  int l0 = int(lod);
  float f = lod - float(l0);
  vec4 a = SampleLevel(s, t, l0, uv);
  if (f == 0.0f) return a;
  return (1.0f - f) * a + f * SampleLevel(s, t, l0 + 1, uv);
}

// Texture coordinates at a surface point, per UV set, with the width of the point's footprint
// in each set's units (0: none known, so level 0 is read).
struct TexCoords {
  vec2 uv[2];
  float width[2];
};

// A material slot's lookup: the reference's UV set through KHR_texture_transform, at the level
// its footprint asks for (the transform's scale widens it too).
PT_HDI vec4 SampleTextureRef(const SceneView& s, int32_t refIndex, const TexCoords& tc) {
  const TextureRef& r = s.textureRefs[refIndex];
  uint32_t set = r.texCoord != 0 ? 1u : 0u;
  vec3 uv1(tc.uv[set], 1.0f);
  vec2 uv(glm::dot(r.row0, uv1), glm::dot(r.row1, uv1));
  float lod = 0.0f;
  if (tc.width[set] > 0.0f) {
    const Texture& t = s.textures[r.texture];
    float det = fabsf(r.row0.x * r.row1.y - r.row0.y * r.row1.x);
    float texels = tc.width[set] * sqrtf(det * float(t.width) * float(t.height));
    lod = texels > 0.0f ? log2f(texels) : 0.0f;
  }
  return SampleTexture(s, r.texture, uv, lod);
}

}  // namespace pt
