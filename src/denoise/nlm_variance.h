// The halves' variances calibrated against the halves themselves (--denoise-variance
// calibrated; docs/denoise.md). The film's per-pixel sample variance over n says how far a
// mean of n independent samples strays; stratified samples (--sampler sobol) stray far less,
// so the filter, reading each colour difference in units of that variance, takes detail for
// noise and blurs it (the Sobol-sampled image came out worse denoised than raw). Rousselle,
// Knaus and Zwicker (2012, sec. 4.2) scale the sample variance by the ratio of the two half
// buffers' squared difference, unbiased when the halves are independent (under Sobol the
// sampler makes them two replicates: rng.h, kSobolHalves) but noisy, to what the sample
// variance predicts for it, both summed over a window. The ratio is at most 1 (the
// calibration only ever lowers the estimate) and 1 where the window has no variance.
//
// Three passes over the padded pixels, run after DenoiseFillPixel and before the outlier
// passes. They borrow four planes that later passes fill (the feature scales and a
// candidate's error estimate).
#pragma once

#include "src/denoise/nlm_stages.h"

namespace pt {

constexpr int kVarianceWindowRadius = 7;  // the sums' window: 15 x 15 pixels

PT_HDI float* CalibrationTerm(const DenoisePlanes& d, int k) {
  return k < 3 ? d.featureScale[k] : d.error[0];
}

// Pass 1: the halves' squared difference and its predicted value, summed over the channels
// (0: measured, 1: predicted).
PT_HDI void DenoiseVarianceTermsPixel(const DenoisePlanes& d, uint32_t i) {
  float measured = 0.0f, predicted = 0.0f;
  for (int c = 0; c < 3; ++c) {
    float delta = d.half[0][c][i] - d.half[1][c][i];
    measured += delta * delta;
    predicted += d.halfVar[0][c][i] + d.halfVar[1][c][i];
  }
  CalibrationTerm(d, 0)[i] = measured;
  CalibrationTerm(d, 1)[i] = predicted;
}

// Pass 2: both summed along the row (2: measured, 3: predicted), the window clamped to the
// padded row (whose ends repeat the image's edge pixels).
PT_HDI void DenoiseVarianceRowPixel(const DenoisePlanes& d, uint32_t i) {
  int32_t x = int32_t(i % d.stride), rowStart = int32_t(i) - x;
  float measured = 0.0f, predicted = 0.0f;
  for (int dx = -kVarianceWindowRadius; dx <= kVarianceWindowRadius; ++dx) {
    int32_t q = x + dx < 0 ? 0 : (x + dx >= int32_t(d.stride) ? int32_t(d.stride) - 1 : x + dx);
    measured += CalibrationTerm(d, 0)[rowStart + q];
    predicted += CalibrationTerm(d, 1)[rowStart + q];
  }
  CalibrationTerm(d, 2)[i] = measured;
  CalibrationTerm(d, 3)[i] = predicted;
}

// Pass 3: the row sums summed down the column; each half's variances scaled by the ratio. A
// padding pixel takes the ratio of the image pixel it repeats, so the padding stays a repeat
// of the edge (as the outlier passes keep it).
PT_HDI void DenoiseVarianceScalePixel(const DenoisePlanes& d, uint32_t i) {
  uint32_t imageX, imageY;
  RepeatedImagePixel(d, i, &imageX, &imageY);
  size_t centre = d.Padded(imageX, imageY);
  int32_t y = int32_t(centre / d.stride), x = int32_t(centre % d.stride);
  float measured = 0.0f, predicted = 0.0f;
  for (int dy = -kVarianceWindowRadius; dy <= kVarianceWindowRadius; ++dy) {
    int32_t r = y + dy < 0 ? 0 : (y + dy >= int32_t(d.rows) ? int32_t(d.rows) - 1 : y + dy);
    size_t q = size_t(r) * d.stride + size_t(x);
    measured += CalibrationTerm(d, 2)[q];
    predicted += CalibrationTerm(d, 3)[q];
  }
  float ratio = predicted > 0.0f && measured < predicted ? measured / predicted : 1.0f;
  for (int h = 0; h < kDenoiseHalves; ++h) {
    for (int c = 0; c < 3; ++c) d.halfVar[h][c][i] *= ratio;
  }
}

}  // namespace pt
