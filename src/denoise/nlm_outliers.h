// The denoiser's outlier passes (src/denoise/denoise_runner.h), run on each half before the
// NL-means passes: the outlier detection of Cycles' former NL-means denoiser. A firefly (one
// rare sample of a bright path: the sun through a window reached by a diffuse bounce) is
// spread by the filter over every pixel that accepts it, and the estimate of its own error
// (SURE) cannot tell it from detail. A pixel is an outlier of its half when its luminance is
// above twice the 75th percentile of its 5x5 neighbourhood's and either its variance is more
// than 9 times its neighbours' largest or that reference lies within 3 standard deviations
// of it (a legitimate highlight lies further). An outlier's colour is scaled down to the
// reference (biased: its energy is lost) and its variance becomes the neighbours' largest
// (or scales with the colour); docs/denoise.md.
//
// Three bodies, so that the CPU vectorises the costly one: Detect counts the neighbours under
// the threshold (no loop left once unrolled); Resolve does the rest for the few pixels Detect
// flagged; Apply writes the result into every padded pixel repeating an image pixel.
#pragma once

#include "src/denoise/nlm_stages.h"

namespace pt {

constexpr int kOutlierRadius = 2;  // the 5x5 neighbourhood
constexpr int kOutlierCount = (2 * kOutlierRadius + 1) * (2 * kOutlierRadius + 1);
// The 75th percentile's rank among the 25 (Cycles' int(n * 0.75)).
constexpr int kOutlierRank = kOutlierCount * 3 / 4;
// Absolute offsets that keep (almost) black areas from false positives, radiance units.
constexpr float kOutlierLumOffset = 1e-5f, kOutlierVarOffset = 1.1e-4f;

// The planes the outlier passes use: each half's luminance, the colour's scale (1 where no
// outlier; 0 from Detect where Resolve must look) and the variance an outlier takes
// (negative: its own, scaled with the colour). Borrowed from planes the later passes fill
// (the feature scales, the candidates' error estimates) and no pass reads before then: the
// CPU keeps no whole-image distance planes (denoise_tiles.h).
PT_HDI float* OutlierLum(const DenoisePlanes& d, int h) { return d.featureScale[h]; }
PT_HDI float* OutlierScale(const DenoisePlanes& d, int h) {
  return h == 0 ? d.featureScale[2] : d.error[0];
}
PT_HDI float* OutlierNewVar(const DenoisePlanes& d, int h) { return d.error[1 + h]; }
static_assert(kDenoiseCandidates >= 3, "the outlier passes borrow three error planes");

// The mean of a half's channel variances at p.
PT_HDI float MeanHalfVar(const DenoisePlanes& d, int h, size_t p) {
  return (d.halfVar[h][0][p] + d.halfVar[h][1][p] + d.halfVar[h][2][p]) * (1.0f / 3.0f);
}

// Pass O1, per padded pixel: each half's luminance (the mean of its non-negative channels).
PT_HDI void DenoiseOutlierLumPixel(const DenoisePlanes& d, size_t p) {
  PT_DENOISE_UNROLL
  for (int h = 0; h < kDenoiseHalves; ++h) {
    float lum = 0.0f;
    PT_DENOISE_UNROLL
    for (int c = 0; c < 3; ++c) lum += DenoiseMax(d.half[h][c][p], 0.0f);
    OutlierLum(d, h)[p] = lum * (1.0f / 3.0f);
  }
}

// Pass O2, per padded pixel of the image rows: 0 (look closer) where the pixel's luminance is
// above the reference, i.e. where at least kOutlierRank + 1 of the 25 luminances (its own
// among them) lie below half of it; else 1 (no outlier).
PT_HDI void DenoiseOutlierDetectPixel(const DenoisePlanes& d, size_t p) {
  ptrdiff_t stride = ptrdiff_t(d.stride);
  PT_DENOISE_UNROLL
  for (int h = 0; h < kDenoiseHalves; ++h) {
    const float* lum = OutlierLum(d, h);
    float own = lum[p];
    float below = 0.0f;
    PT_DENOISE_UNROLL
    for (int dy = -kOutlierRadius; dy <= kOutlierRadius; ++dy) {
      PT_DENOISE_UNROLL
      for (int dx = -kOutlierRadius; dx <= kOutlierRadius; ++dx) {
        float v = lum[ptrdiff_t(p) + dy * stride + dx];
        below += 2.0f * v - kOutlierLumOffset < own ? 1.0f : 0.0f;
      }
    }
    OutlierScale(d, h)[p] = below > float(kOutlierRank) ? 0.0f : 1.0f;
    OutlierNewVar(d, h)[p] = -1.0f;
  }
}

// The k-th smallest of n values (insertion sort: few pixels get here).
PT_HDI float KthSmallest(float* v, int n, int k) {
  for (int i = 1; i < n; ++i) {
    float x = v[i];
    int j = i - 1;
    for (; j >= 0 && v[j] > x; --j) v[j + 1] = v[j];
    v[j + 1] = x;
  }
  return v[k];
}

// One half of a flagged pixel: the reference, the variance test, the scale and new variance.
PT_HDI void ResolveOutlier(const DenoisePlanes& d, int h, size_t p) {
  ptrdiff_t stride = ptrdiff_t(d.stride);
  const float* lum = OutlierLum(d, h);
  float values[kOutlierCount];
  float maxVar = 0.0f;
  int n = 0;
  for (int dy = -kOutlierRadius; dy <= kOutlierRadius; ++dy) {
    for (int dx = -kOutlierRadius; dx <= kOutlierRadius; ++dx) {
      ptrdiff_t q = ptrdiff_t(p) + dy * stride + dx;
      values[n++] = lum[q];
      if (dy != 0 || dx != 0) maxVar = DenoiseMax(maxVar, MeanHalfVar(d, h, size_t(q)));
    }
  }
  maxVar += kOutlierVarOffset;
  float ref = DenoiseMax(2.0f * KthSmallest(values, n, kOutlierRank) - kOutlierLumOffset, 0.0f);
  float own = lum[p], ownVar = MeanHalfVar(d, h, p);
  // Detect's test less the clamp of ref at 0: a black pixel (of a noisy half) is no outlier.
  float scale = own > ref ? ref / own : 1.0f;
  if (scale == 1.0f) {
    OutlierScale(d, h)[p] = 1.0f;
  } else if (ownVar > 9.0f * maxVar) {
    OutlierScale(d, h)[p] = scale;
    OutlierNewVar(d, h)[p] = maxVar;
  } else if (own - 3.0f * sqrtf(ownVar) < ref) {
    OutlierScale(d, h)[p] = scale;
  } else {
    OutlierScale(d, h)[p] = 1.0f;  // a legitimate highlight
  }
}

// Pass O3, per padded pixel of the image rows: resolves the pixels Detect flagged.
PT_HDI void DenoiseOutlierResolvePixel(const DenoisePlanes& d, size_t p) {
  for (int h = 0; h < kDenoiseHalves; ++h) {
    if (OutlierScale(d, h)[p] == 0.0f) ResolveOutlier(d, h, p);
  }
}

// Pass O4, per padded pixel: the image pixel's outcome applied to it and to the padding that
// repeats it (as DenoiseFillPixel repeats the values).
PT_HDI void DenoiseOutlierApplyPixel(const DenoisePlanes& d, uint32_t i) {
  uint32_t x, y;
  RepeatedImagePixel(d, i, &x, &y);
  uint32_t s = d.Padded(x, y);
  for (int h = 0; h < kDenoiseHalves; ++h) {
    float scale = OutlierScale(d, h)[s];
    if (scale == 1.0f) continue;
    float newVar = OutlierNewVar(d, h)[s];
    for (int c = 0; c < 3; ++c) {
      d.half[h][c][i] *= scale;
      d.halfVar[h][c][i] = newVar >= 0.0f ? newVar : d.halfVar[h][c][i] * scale * scale;
    }
  }
}

}  // namespace pt
