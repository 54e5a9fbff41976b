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
  vec3* evenSum;            // the even-indexed samples' sum and count: one of the two half
  uint32_t* evenCount;      // films a denoiser compares (null unless requested)
};

// A pixel with no samples: every channel the film keeps set to zero (ResetFilm's stage body).
PT_HDI void ClearFilmPixel(const FilmView& f, uint32_t i) {
  if (f.mean) f.mean[i] = f.m2[i] = vec3(0.0f);
  if (f.meanDouble) f.meanDouble[i] = f.m2Double[i] = glm::dvec3(0.0);
  f.lumMean[i] = f.lumM2[i] = 0.0f;
  f.sampleCount[i] = 0u;
  if (f.albedoSum) f.albedoSum[i] = f.normalSum[i] = vec3(0.0f);
  if (f.depthSum) f.depthSum[i] = 0.0f;
  if (f.evenSum) {
    f.evenSum[i] = vec3(0.0f);
    f.evenCount[i] = 0u;
  }
}

// A pixel of one film copied into another of the same channels (SnapshotFilm's stage body).
PT_HDI void CopyFilmPixel(const FilmView& to, const FilmView& from, uint32_t i) {
  if (from.mean) {
    to.mean[i] = from.mean[i];
    to.m2[i] = from.m2[i];
  }
  if (from.meanDouble) {
    to.meanDouble[i] = from.meanDouble[i];
    to.m2Double[i] = from.m2Double[i];
  }
  to.lumMean[i] = from.lumMean[i];
  to.lumM2[i] = from.lumM2[i];
  to.sampleCount[i] = from.sampleCount[i];
  if (from.albedoSum) {
    to.albedoSum[i] = from.albedoSum[i];
    to.normalSum[i] = from.normalSum[i];
  }
  if (from.depthSum) to.depthSum[i] = from.depthSum[i];
  if (from.evenSum) {
    to.evenSum[i] = from.evenSum[i];
    to.evenCount[i] = from.evenCount[i];
  }
}

template <typename V, typename R>
PT_HDI void WelfordAdd(V& mean, V& m2, V x, R n) {
  V delta = x - mean;
  mean += delta / n;
  m2 += delta * (x - mean);
}

}  // namespace pt
