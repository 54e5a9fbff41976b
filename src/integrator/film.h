// The film: per-pixel running statistics over the crop window, updated with Welford's
// algorithm (numerically stable mean and variance). Each pixel is written by one work item
// that adds the wave's samples in sample order, so updates never race and never reorder.
#pragma once

#include "src/core/math.h"

namespace pt {

struct FilmView {
  vec3* mean;               // float film (--film float)
  vec3* m2;
  glm::dvec3* meanDouble;   // double film (--film double); null otherwise
  glm::dvec3* m2Double;
  float* lumMean;           // Welford of Rec. 709 luminance, for adaptive sampling
  float* lumM2;
  uint32_t* sampleCount;
  vec3* albedoSum;          // feature sums; null unless requested
  vec3* normalSum;
  float* depthSum;
};

template <typename V, typename R>
PT_HDI void WelfordAdd(V& mean, V& m2, V x, R n) {
  V delta = x - mean;
  mean += delta / n;
  m2 += delta * (x - mean);
}

}  // namespace pt
