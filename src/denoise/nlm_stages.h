// The denoiser's per-pixel bodies, run by both backends (src/denoise/denoise_runner.h).
//
// Rousselle, Knaus and Zwicker's NL-means filter on the film's two half buffers (2012): each
// half is filtered with weights computed on the other, so the weights do not follow the noise
// of what they average; a neighbour's weight is the smaller of the NL-means colour weight and
// the feature weight of Rousselle, Manzi and Zwicker (2013) on albedo, normal and depth. As in
// the latter, several candidate filters (bandwidths from strict to loose) run at once, and
// each pixel takes the candidate of least estimated error (SURE, exact here: a cross-filtered
// half is linear in the values it averages), the estimates smoothed over a small window. The
// image is the mean of the two filtered halves.
//
// Everything works on planes of floats over the image padded by the search radius and the
// patch radius (edge pixels repeated), so that a neighbour at a fixed offset is a fixed step
// in memory: the CPU vectorises the per-offset passes, and no body tests the image's bounds.
#pragma once

#include "src/core/math.h"

// Loops over candidates and channels unrolled: GCC vectorises a pass over the pixels only
// when its body has no loop left.
#if defined(__CUDACC__)
#define PT_DENOISE_UNROLL _Pragma("unroll")
#else
#define PT_DENOISE_UNROLL _Pragma("GCC unroll 16")
#endif

namespace pt {

// Half-buffer index: 0 holds the even-indexed samples (A), 1 the odd ones (B).
constexpr int kDenoiseHalves = 2;
constexpr int kDenoiseCandidates = 3;  // candidate filters (denoise_settings.h)
// Offsets of one row of the window handled per pass: the sums stay in registers across them
// (a GPU reads and writes them from memory once per group instead of once per offset).
constexpr int kDenoiseGroup = 8;
// The CPU's groups for the default patch: a window row of up to 15 columns (radius 7) in one
// group. Loading and storing a tile's 24 sums costs about 2.5 offsets' work there (L2, not
// registers); one group a row instead of two saved 11% of the passes at radius 7.
constexpr int kDenoiseWideGroup = 15;

struct DenoisePlanes {
  uint32_t width = 0, height = 0;    // the image
  uint32_t padX = 0, padY = 0;       // columns and rows of padding on each side
  uint32_t stride = 0, rows = 0;     // padded row length and row count
  float* half[kDenoiseHalves][3];    // each half's mean (RGB)
  float* halfVar[kDenoiseHalves][3]; // the variance of that mean
  float* albedo[3];
  float* normal[3];
  float* depth;
  // Per pixel, 1 / max(tau, |grad f|^2) for albedo, normal and depth (depth relative).
  float* featureScale[3];
  // One group of offsets' pixel-wise NL-means distances, per offset and guide.
  float* dist[kDenoiseWideGroup][kDenoiseHalves];
  // Per candidate and filtered half: weighted colour differences (RGB) and the weight sum.
  float* sum[kDenoiseCandidates][kDenoiseHalves][4];
  float* error[kDenoiseCandidates];  // per candidate, its SURE error estimate

  PT_HDI uint32_t Padded(uint32_t x, uint32_t y) const { return (y + padY) * stride + x + padX; }
};

// The film's image as the denoiser reads it (interleaved arrays as in FilmImage).
struct DenoiseInput {
  const float* rgb;          // mean of all samples
  const float* variance;     // per-channel sample variance
  const uint32_t* samples;
  const float* evenRgb;      // mean of the even-indexed samples
  const uint32_t* evenSamples;
  const float* albedo;
  const float* normal;
  const float* depth;
  // The seen emission's means and the residual's variance (FilmImage::emission), or null: the
  // passes filter the residual, and DenoiseAddEmissionPixel adds the emission back.
  const float* emission;
  const float* evenEmission;
  const float* residualVariance;
};

// e^x for x <= 0 (larger x are not asked for), relative error about 2e-7: 2^(x log2 e) as a
// power of two times Cephes' polynomial for 2^f on [-1/2, 1/2], the power rounded to nearest
// by adding and taking away 1.5 * 2^23. Plain arithmetic and selects of computed values, which
// the CPU vectorises (std::exp and floorf are calls there, and GCC will not turn a branch that
// computes into a select), evaluated alike by both backends. Below e^-30 it is 0: a weight that
// small changes nothing, and its products would be denormals (slow on a CPU).
PT_HDI float DenoiseExp(float x) {
  constexpr float kRound = 12582912.0f;
  float t = (x > -30.0f ? x : -30.0f) * 1.44269504088896341f;
  float n = (t + kRound) - kRound;
  float f = t - n;
  float p = 1.535336188319500e-4f;
  p = p * f + 1.339887440266574e-3f;
  p = p * f + 9.618437357674640e-3f;
  p = p * f + 5.550332471162809e-2f;
  p = p * f + 2.402264791363012e-1f;
  p = p * f + 6.931472028550421e-1f;
  p = p * f + 1.0f;
  int32_t bits = (int32_t(n) + 127) * (1 << 23);
#if PT_IS_GPU_CODE
  float scale = __int_as_float(bits);
#else
  float scale;
  __builtin_memcpy(&scale, &bits, sizeof(scale));
#endif
  float value = p * scale;
  return x < -30.0f ? 0.0f : value;
}

// Inputs as the passes take them: non-finite values as 0, magnitudes at most `limit` (colour
// and features 1e16, variances 1e32), so that no square, sum or ratio below overflows.
PT_HDI float Sanitized(float v, float limit) {
  v = v - v == 0.0f ? v : 0.0f;
  return v > limit ? limit : (v < -limit ? -limit : v);
}
constexpr float kDenoiseValueLimit = 1e16f, kDenoiseVarianceLimit = 1e32f;
// fmaxf and fminf without their NaN rules (no NaN reaches them): selects the CPU vectorises,
// where fmaxf is a call.
PT_HDI float DenoiseMax(float a, float b) { return a > b ? a : b; }
PT_HDI float DenoiseMin(float a, float b) { return a < b ? a : b; }

// The image pixel a padded pixel i is or repeats (the nearest one, for the padding).
PT_HDI void RepeatedImagePixel(const DenoisePlanes& d, uint32_t i, uint32_t* x, uint32_t* y) {
  int32_t px = int32_t(i % d.stride) - int32_t(d.padX);
  int32_t py = int32_t(i / d.stride) - int32_t(d.padY);
  *x = uint32_t(px < 0 ? 0 : (px >= int32_t(d.width) ? int32_t(d.width) - 1 : px));
  *y = uint32_t(py < 0 ? 0 : (py >= int32_t(d.height) ? int32_t(d.height) - 1 : py));
}

// Pass 1, over every padded pixel: the halves' means and variances, and the features, from
// the image pixel the padding repeats; the sums zeroed. A pixel with one sample (or none)
// has both halves equal to its mean.
PT_HDI void DenoiseFillPixel(const DenoisePlanes& d, const DenoiseInput& in, uint32_t i) {
  uint32_t x, y;
  RepeatedImagePixel(d, i, &x, &y);
  size_t s = size_t(y) * d.width + size_t(x);
  uint32_t n = in.samples[s], na = in.evenSamples[s] < n ? in.evenSamples[s] : n, nb = n - na;
  constexpr float kLimit = kDenoiseValueLimit;
  const bool residual = in.emission != nullptr;
  for (int c = 0; c < 3; ++c) {
    float mean = Sanitized(in.rgb[3 * s + c], kLimit);
    float a = na > 0 ? Sanitized(in.evenRgb[3 * s + c], kLimit) : mean;
    if (residual) {  // the halves less the emission their camera rays saw
      float e = Sanitized(in.emission[3 * s + c], kLimit);
      a = Sanitized(a - (na > 0 ? Sanitized(in.evenEmission[3 * s + c], kLimit) : e), kLimit);
      mean = Sanitized(mean - e, kLimit);
    }
    // The odd samples' mean from the whole mean and the even one (float rounding aside).
    float b = nb > 0 && na > 0 ? (float(n) * mean - float(na) * a) / float(nb) : a;
    const float* variance = residual ? in.residualVariance : in.variance;
    float var = DenoiseMax(Sanitized(variance[3 * s + c], kDenoiseVarianceLimit), 0.0f);
    d.half[0][c][i] = a;
    d.half[1][c][i] = Sanitized(b, kLimit);
    d.halfVar[0][c][i] = var / float(na > 1 ? na : 1);
    d.halfVar[1][c][i] = var / float(nb > 1 ? nb : 1);
    d.albedo[c][i] = Sanitized(in.albedo[3 * s + c], kLimit);
    d.normal[c][i] = Sanitized(in.normal[3 * s + c], kLimit);
  }
  d.depth[i] = DenoiseMax(Sanitized(in.depth[s], kLimit), 0.0f);
  for (int k = 0; k < kDenoiseCandidates; ++k) {
    for (int h = 0; h < kDenoiseHalves; ++h) {
      for (int c = 0; c < 4; ++c) d.sum[k][h][c][i] = 0.0f;
    }
  }
}

// Squared gradient of a feature of `channels` planes at padded pixel p: per axis the central
// difference's, or with `oneSided` the smaller of the two one-sided differences' (a slope has
// it on both sides, a step only on one, so a step keeps its full weight).
PT_HDI float FeatureGradient2(float* const* planes, int channels, uint32_t p, uint32_t stride,
                              bool oneSided) {
  float g = 0.0f;
  for (int c = 0; c < channels; ++c) {
    const float* f = planes[c];
    float xl = f[p] - f[p - 1], xr = f[p + 1] - f[p];
    float yl = f[p] - f[p - stride], yr = f[p + stride] - f[p];
    float xc = 0.5f * (xl + xr), yc = 0.5f * (yl + yr);
    g += oneSided ? DenoiseMin(xl * xl, xr * xr) + DenoiseMin(yl * yl, yr * yr)
                  : xc * xc + yc * yc;
  }
  return g;
}

// Pass 2, over the padded pixels of rows 1 .. rows - 2 (i counts from row 1): each feature's
// scale, 1 / max(tau, |grad f|^2) (the candidates divide by their k_f^2), so that a feature
// changing across a pixel anyway (a slanted floor's depth) weighs no more than its own change.
// Depth is measured relative to the pixel's own (scale-free); a zero depth (the background)
// has scale 0 and leaves depth out.
PT_HDI void DenoiseFeatureScalePixel(const DenoisePlanes& d, float tau, uint32_t i) {
  uint32_t p = d.stride + i;
  constexpr float k2 = 1.0f;
  // 1e-30: tau * z^2 of a depth near 0 underflows; the scale stays finite (0 * scale = 0).
  tau = DenoiseMax(tau, 1e-30f);
  // Albedo steps (textures, material boundaries) stay sharp; normals and depth change across
  // a pixel at every antialiased silhouette, where a strict measure would keep the noise.
  float ga = FeatureGradient2(d.albedo, 3, p, d.stride, true);
  float gn = FeatureGradient2(d.normal, 3, p, d.stride, false);
  d.featureScale[0][p] = 1.0f / (k2 * DenoiseMax(tau, ga));
  d.featureScale[1][p] = 1.0f / (k2 * DenoiseMax(tau, gn));
  float z = d.depth[p];
  float gz = FeatureGradient2(&d.depth, 1, p, d.stride, false);
  float zScale = DenoiseMax(DenoiseMax(tau * z * z, gz), 1e-30f);
  d.featureScale[2][p] = z > 0.0f ? 1.0f / (k2 * zScale) : 0.0f;
}

// Pass 3, per offset, over the padded pixels of a band of rows widened by the patch radius:
// each guide's NL-means distance between pixel p and p + offset (Rousselle et al. 2012, eq. 5
// per pixel, with k_c = 1: the candidates divide by their k_c^2): the squared difference less
// the variance it is expected to have, over the variance, averaged over the channels. It is
// taken as 0 where negative: a patch's mean would otherwise let two high-variance pixels (an
// emitter's antialiased edge) outweigh a clear difference at another, and a dark pixel beside
// a light would take in its radiance.
PT_HDI float PixelDistance(float* const* mean, float* const* var, size_t p, size_t q) {
  float sum = 0.0f;
  for (int c = 0; c < 3; ++c) {
    float delta = mean[c][p] - mean[c][q];
    float vp = var[c][p], vq = var[c][q];
    sum += (delta * delta - (vp + DenoiseMin(vp, vq))) / (1e-10f + (vp + vq));
  }
  return DenoiseMax(sum * (1.0f / 3.0f), 0.0f);
}

// A group of offsets: row offset `row` (dy * stride) and columns first .. first + count - 1.
// The passes are compiled for each group size (their kGroup is count), so no slot is computed
// only to be weighted 0. A window row of at most maxGroup columns is one group; a longer one
// is cut into groups of kDenoiseGroup from the left, the last of 1, 3, 5 or 7 (rows have
// 2 radius + 1 columns). Sizes: 1, 3, 5, 7, 8 and, with maxGroup 15, 9 .. 15 odd.
struct DenoiseOffsets {
  ptrdiff_t row;
  int first, count;
  PT_HDI ptrdiff_t Of(int g) const { return row + first + g; }
  // The group of window row dy from column dx.
  static PT_HDI DenoiseOffsets Group(int dy, int dx, int radius, uint32_t stride,
                                     int maxGroup = kDenoiseGroup) {
    int size = 2 * radius + 1 <= maxGroup ? 2 * radius + 1 : kDenoiseGroup;
    return DenoiseOffsets{ptrdiff_t(dy) * ptrdiff_t(stride), dx,
                          size < radius - dx + 1 ? size : radius - dx + 1};
  }
};
static_assert(kDenoiseGroup == 8, "the backends' group-size switches list 8, 7, 5, 3 and 1");

template <int kGroup>
PT_HDI void DenoiseDistancePixel(const DenoisePlanes& d, const DenoiseOffsets& o, size_t p) {
  PT_DENOISE_UNROLL
  for (int g = 0; g < kGroup; ++g) {
    size_t q = size_t(ptrdiff_t(p) + o.Of(g));
    d.dist[g][0][p] = PixelDistance(d.half[0], d.halfVar[0], p, q);
    d.dist[g][1][p] = PixelDistance(d.half[1], d.halfVar[1], p, q);
  }
}

// The mean of a guide's pixel distances over the patch around p.
template <int kPatch>
PT_HDI float PatchDistance(const float* dist, size_t p, ptrdiff_t stride) {
  float s = 0.0f;
  for (int dy = -kPatch; dy <= kPatch; ++dy) {
    for (int dx = -kPatch; dx <= kPatch; ++dx) s += dist[ptrdiff_t(p) + dy * stride + dx];
  }
  return s * (1.0f / float((2 * kPatch + 1) * (2 * kPatch + 1)));
}

// The feature distance of p and q: the largest of the scaled squared differences.
PT_HDI float FeatureDistance(const DenoisePlanes& d, size_t p, size_t q) {
  float da = 0.0f, dn = 0.0f;
  for (int c = 0; c < 3; ++c) {
    float a = d.albedo[c][p] - d.albedo[c][q], n = d.normal[c][p] - d.normal[c][q];
    da += a * a;
    dn += n * n;
  }
  float dz = d.depth[p] - d.depth[q];
  return DenoiseMax(DenoiseMax(da * d.featureScale[0][p], dn * d.featureScale[1][p]),
               dz * dz * d.featureScale[2][p]);
}

// The sums hold weighted differences from the pixel's own value: a neighbour equal to it adds
// exactly nothing (a constant image stays exactly constant), and the sum of 225 terms keeps
// the precision of the differences rather than of the values.
PT_HDI void AddNeighbour(float* sum, float* const* mean, const float* own, size_t q, float w) {
  PT_DENOISE_UNROLL
  for (int c = 0; c < 3; ++c) sum[c] += w * (mean[c][q] - own[c]);
  sum[3] += w;
}

// The candidates' bandwidths as the passes use them: 1 / k^2 (colour, features).
struct DenoiseBandwidths {
  float color[kDenoiseCandidates];
  float feature[kDenoiseCandidates];
};

// Pass 4, per group of offsets, over the padded pixels of a band of rows: for each offset
// in turn and each candidate, each half's sums take the neighbour with weight
// exp(-max(patch distance of the OTHER half, feature distance)), both in that candidate's
// bandwidths. The same additions in the same order as one offset at a time. kGroup is the
// group's count (o.count).
template <int kPatch, int kGroup>
PT_HDI void DenoiseAccumulatePixel(const DenoisePlanes& d, const DenoiseBandwidths& k,
                                   const DenoiseOffsets& o, size_t p) {
  ptrdiff_t stride = ptrdiff_t(d.stride);
  float sum[kDenoiseCandidates][kDenoiseHalves][4], own[kDenoiseHalves][3];
  PT_DENOISE_UNROLL
  for (int h = 0; h < kDenoiseHalves; ++h) {
    PT_DENOISE_UNROLL
    for (int c = 0; c < 3; ++c) own[h][c] = d.half[h][c][p];
    PT_DENOISE_UNROLL
    for (int j = 0; j < kDenoiseCandidates; ++j) {
      PT_DENOISE_UNROLL
      for (int c = 0; c < 4; ++c) sum[j][h][c] = d.sum[j][h][c][p];
    }
  }
  PT_DENOISE_UNROLL
  for (int g = 0; g < kGroup; ++g) {
    size_t q = size_t(ptrdiff_t(p) + o.Of(g));
    float feature = FeatureDistance(d, p, q);
    float patch0 = PatchDistance<kPatch>(d.dist[g][0], p, stride);
    float patch1 = PatchDistance<kPatch>(d.dist[g][1], p, stride);
    PT_DENOISE_UNROLL
    for (int j = 0; j < kDenoiseCandidates; ++j) {
      float f = feature * k.feature[j];
      float w0 = DenoiseExp(-DenoiseMax(patch1 * k.color[j], f));
      float w1 = DenoiseExp(-DenoiseMax(patch0 * k.color[j], f));
      AddNeighbour(sum[j][0], d.half[0], own[0], q, w0);
      AddNeighbour(sum[j][1], d.half[1], own[1], q, w1);
    }
  }
  PT_DENOISE_UNROLL
  for (int h = 0; h < kDenoiseHalves; ++h) {
    PT_DENOISE_UNROLL
    for (int j = 0; j < kDenoiseCandidates; ++j) {
      PT_DENOISE_UNROLL
      for (int c = 0; c < 4; ++c) d.sum[j][h][c][p] = sum[j][h][c];
    }
  }
}

// Pass 5, per padded pixel of the image rows: each candidate's error estimate, the sum over
// both halves and the channels of Stein's unbiased risk estimate. A half filtered with the
// other's weights is F = y + S / W, linear in y with dF_p/dy_p = 1 / W (its own weight is
// 1), so SURE = (F - y)^2 + var (2 / W - 1) is unbiased.
PT_HDI void DenoiseErrorPixel(const DenoisePlanes& d, int count, size_t p) {
  // Relative to the value the strictest candidate gives (the error measure is relMSE's).
  float scale[3];
  for (int c = 0; c < 3; ++c) {
    float v = 0.0f;
    for (int h = 0; h < kDenoiseHalves; ++h)
      v += 0.5f * (d.half[h][c][p] + d.sum[0][h][c][p] / d.sum[0][h][3][p]);
    scale[c] = 1.0f / (v * v + 1e-2f);
  }
  for (int k = 0; k < count; ++k) {
    float e = 0.0f;
    for (int h = 0; h < kDenoiseHalves; ++h) {
      float w = d.sum[k][h][3][p];
      for (int c = 0; c < 3; ++c) {
        float step = d.sum[k][h][c][p] / w;
        e += (step * step + d.halfVar[h][c][p] * (2.0f / w - 1.0f)) * scale[c];
      }
    }
    d.error[k][p] = e;
  }
}

// Pass 6, over the padded pixels of the rows within the selection radius of the image: the
// error planes' padding repeats their edge pixels (as the other planes' does), so the window
// sums of the selection read the image's edge without a clamp, which the CPU vectorises.
PT_HDI void DenoiseErrorPadPixel(const DenoisePlanes& d, int count, uint32_t i) {
  uint32_t x, y;
  RepeatedImagePixel(d, i, &x, &y);
  size_t edge = d.Padded(x, y);
  if (edge == size_t(i)) return;
  for (int k = 0; k < count; ++k) d.error[k][i] = d.error[k][edge];
}

// The candidate whose window error e[k] is least (the first of equal ones; k < count), and the
// mean of its two filtered halves into rgb. Every candidate's sums are read and the chosen
// one's selected before dividing: the same values as reading only its own, in vector code.
PT_HDI void DenoiseChoosePixel(const DenoisePlanes& d, int count, const float* e, size_t p,
                               float* rgb) {
  int best = 0;
  float bestError = e[0];
  PT_DENOISE_UNROLL
  for (int k = 1; k < kDenoiseCandidates; ++k) {
    bool better = k < count && e[k] < bestError;
    best = better ? k : best;
    bestError = better ? e[k] : bestError;
  }
  PT_DENOISE_UNROLL
  for (int c = 0; c < 3; ++c) {
    float half[kDenoiseHalves];
    PT_DENOISE_UNROLL
    for (int h = 0; h < kDenoiseHalves; ++h) {
      float s[kDenoiseCandidates], w[kDenoiseCandidates];
      PT_DENOISE_UNROLL
      for (int k = 0; k < kDenoiseCandidates; ++k) {
        s[k] = d.sum[k][h][c][p];
        w[k] = d.sum[k][h][3][p];
      }
      PT_DENOISE_UNROLL
      for (int k = 1; k < kDenoiseCandidates; ++k) {
        s[0] = best == k ? s[k] : s[0];
        w[0] = best == k ? w[k] : w[0];
      }
      half[h] = d.half[h][c][p] + s[0] / w[0];
    }
    rgb[c] = 0.5f * (half[0] + half[1]);
  }
}

// Pass 7, per image pixel: the candidate whose error estimate, summed over the window of
// `radius` around the pixel (the padding repeats the edge: pass 6), is least; the mean of its
// two filtered halves, interleaved RGB. (The CPU sums a row's windows in vector loops in the
// same order: DenoiseSelectRow.)
PT_HDI void DenoiseFinishPixel(const DenoisePlanes& d, int count, int radius, float* out,
                               uint32_t i) {
  size_t p = d.Padded(i % d.width, i / d.width);
  ptrdiff_t stride = ptrdiff_t(d.stride);
  float e[kDenoiseCandidates] = {};
  for (int k = 0; k < count; ++k) {
    for (int dy = -radius; dy <= radius; ++dy) {
      const float* error = d.error[k] + (ptrdiff_t(p) + dy * stride);
      for (int dx = -radius; dx <= radius; ++dx) e[k] += error[dx];
    }
  }
  DenoiseChoosePixel(d, count, e, p, out + 3 * size_t(i));
}

// Pass 8, per float of the output (with FilmImage::emission only): the emission the camera
// rays saw added back to the filtered residual, as the film holds it.
PT_HDI void DenoiseAddEmissionPixel(float* out, const float* emission, uint32_t i) {
  out[i] += Sanitized(emission[i], kDenoiseValueLimit);
}

}  // namespace pt
