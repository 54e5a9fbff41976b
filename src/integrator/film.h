// The film: per-pixel running sums over the crop window. Each pixel is written by one work
// item that adds the wave's samples in sample order, so sums never race and never reorder.
#pragma once

#include "src/core/math.h"

namespace pt {

struct FilmView {
  vec3* sum;
  vec3* sumSquares;
  uint32_t* sampleCount;
};

constexpr size_t kFilmBytesPerPixel = 2 * sizeof(vec3) + sizeof(uint32_t);

}  // namespace pt
