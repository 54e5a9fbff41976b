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
  // With the half films: Welford statistics of each sample less the emission its camera ray
  // saw (PathState::featureEmission), and that emission's even-sample sum. The denoiser
  // filters this residual and adds the emission back (null unless half films are kept).
  vec3* residualMean;
  vec3* residualM2;
  vec3* evenEmissionSum;
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
    f.residualMean[i] = f.residualM2[i] = f.evenEmissionSum[i] = vec3(0.0f);
  }
}

// The film resolved to an image's planes (floats, 3 per pixel but depth): null where the film
// keeps no such channel.
struct ImageView {
  float* rgb;
  float* variance;
  float* albedo;
  float* normal;
  float* depth;
  float* evenRgb;
  float* emission;          // with evenRgb: the seen emission's means and the residual's
  float* evenEmission;      // sample variance (FilmView::residualMean)
  float* residualVariance;
};

// A pixel of the film as an image (ResolveFilm's stage body, and ResolveFilmImage's for a
// saved film, whose float statistics were widened to doubles: widening is exact, so a film
// resolved on its backend and the same film saved and resolved on the host give the same
// floats): mean, unbiased sample variance, feature and even-half means (0 without samples),
// and with the half films the seen emission's means and the residual's variance.
PT_HDI void ResolveFilmPixel(const FilmView& f, const ImageView& out, uint32_t i) {
  const double k = double(f.sampleCount[i]);
  const uint32_t even = f.evenSum && k != 0.0 ? f.evenCount[i] : 0u;
  for (int c = 0; c < 3; ++c) {
    const double mean = f.meanDouble ? f.meanDouble[i][c] : double(f.mean[i][c]);
    const double m2 = f.meanDouble ? f.m2Double[i][c] : double(f.m2[i][c]);
    const double variance = k > 1.0 ? m2 / (k - 1.0) : 0.0;
    out.rgb[3 * i + c] = k != 0.0 ? float(mean) : 0.0f;
    out.variance[3 * i + c] = float(0.0 < variance ? variance : 0.0);  // std::max(0, v)'s
    if (out.albedo) {
      out.albedo[3 * i + c] = k != 0.0 ? float(double(f.albedoSum[i][c]) / k) : 0.0f;
      out.normal[3 * i + c] = k != 0.0 ? float(double(f.normalSum[i][c]) / k) : 0.0f;
    }
    if (out.evenRgb) {
      out.evenRgb[3 * i + c] = even > 0 ? float(double(f.evenSum[i][c]) / double(even)) : 0.0f;
      // The emission: the whole mean less the residual's (0 without samples).
      out.emission[3 * i + c] = k != 0.0 ? float(mean - double(f.residualMean[i][c])) : 0.0f;
      out.evenEmission[3 * i + c] =
          even > 0 ? float(double(f.evenEmissionSum[i][c]) / double(even)) : 0.0f;
      double rv = k > 1.0 ? double(f.residualM2[i][c]) / (k - 1.0) : 0.0;
      out.residualVariance[3 * i + c] = float(0.0 < rv ? rv : 0.0);
    }
  }
  if (out.depth) out.depth[i] = k != 0.0 ? float(double(f.depthSum[i]) / k) : 0.0f;
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
    to.residualMean[i] = from.residualMean[i];
    to.residualM2[i] = from.residualM2[i];
    to.evenEmissionSum[i] = from.evenEmissionSum[i];
  }
}

template <typename V, typename R>
PT_HDI void WelfordAdd(V& mean, V& m2, V x, R n) {
  V delta = x - mean;
  mean += delta / n;
  m2 += delta * (x - mean);
}

}  // namespace pt
