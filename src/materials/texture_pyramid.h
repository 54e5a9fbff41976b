// Host-side texture preparation: the sRGB transfer functions and the mip pyramid a texture is
// stored as (RGBA8 levels, each box filtered from the one before, down to 1 x 1; see Texture in
// src/scene/scene_types.h and the lookups in texture.h).
#pragma once

#include <cstdint>
#include <vector>

namespace pt {

// The sRGB EOTF (IEC 61966-2-1): an encoded value in [0, 1] to linear, computed in double.
double SrgbToLinear(double encoded);
// Its inverse, linear in [0, 1] to encoded.
double LinearToSrgb(double linear);
// The EOTF of an 8-bit code, as the lookups decode it (src/materials/srgb_table.h).
float Srgb8ToLinear(uint8_t code);

// Packs RGBA codes as the texel array stores them.
inline uint32_t PackRgba8(uint32_t r, uint32_t g, uint32_t b, uint32_t a) {
  return r | g << 8 | b << 16 | a << 24;
}

// Level 0 (width x height packed RGBA8 texels, rows top to bottom) followed by every smaller
// level: each level's texel averages the area of the previous level it covers (a box filter,
// exact for even sizes, area-weighted for odd ones), RGB in linear light when `srgb` (decoded,
// averaged, encoded again with rounding), alpha linearly. *levels receives the level count.
std::vector<uint32_t> BuildTexturePyramid(uint32_t width, uint32_t height,
                                          const std::vector<uint32_t>& level0, bool srgb,
                                          uint32_t* levels);

}  // namespace pt
