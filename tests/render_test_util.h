// Helpers for tests that render whole scenes: load from inline JSON, render on a backend,
// and compare images statistically with tolerances derived from the film's own variance.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/integrator/render_api.h"
#include "src/io/scene_loader.h"
#include "tests/test_util.h"
#include "tests/z_scores.h"

namespace pt::test {

inline Scene SceneFromJson(const std::string& json) {
  return BuildScene(LoadSceneFromString(json, "inline-test-scene.json", "."));
}

// A scene of the repository at a small size and sample count.
inline Scene SmallScene(const std::string& path, int width, int height, int spp) {
  SceneDesc desc = LoadScene(path);
  desc.render.width = width;
  desc.render.height = height;
  desc.render.spp = spp;
  return BuildScene(std::move(desc));
}

// Bit-identical colour: the same size and the same floats.
inline bool SameImage(const FilmImage& a, const FilmImage& b) {
  return a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

// The same film bit for bit: size, statistics, counts, feature and half-film channels.
inline bool SameFilm(const FilmState& a, const FilmState& b) {
  return a.width == b.width && a.height == b.height && BitIdentical(a.mean, b.mean) &&
         BitIdentical(a.m2, b.m2) && BitIdentical(a.lumMean, b.lumMean) &&
         BitIdentical(a.lumM2, b.lumM2) && BitIdentical(a.count, b.count) &&
         BitIdentical(a.albedoSum, b.albedoSum) && BitIdentical(a.normalSum, b.normalSum) &&
         BitIdentical(a.depthSum, b.depthSum) && BitIdentical(a.evenSum, b.evenSum) &&
         BitIdentical(a.evenCount, b.evenCount) && BitIdentical(a.residualMean, b.residualMean) &&
         BitIdentical(a.residualM2, b.residualM2) &&
         BitIdentical(a.evenEmissionSum, b.evenEmissionSum);
}

inline RenderResult RenderOnCpu(const Scene& scene, RenderOptions options = {}) {
  if (options.threads == 0) options.threads = 2;
  return RenderCpu(scene, options);
}

// Mean of channel c over a pixel window, and the variance of that mean (pixels independent).
struct WindowMean {
  double mean = 0.0;
  double varianceOfMean = 0.0;
};

inline WindowMean MeanOverWindow(const FilmImage& img, int c, int x0, int y0, int x1, int y1) {
  WindowMean w;
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      size_t i = size_t(y) * img.width + x;
      w.mean += img.rgb[3 * i + c];
      w.varianceOfMean += img.variance[3 * i + c] / std::max(1u, img.samples[i]);
      ++n;
    }
  w.mean /= n;
  w.varianceOfMean /= double(n) * n;
  return w;
}

inline WindowMean MeanOverImage(const FilmImage& img, int c) {
  return MeanOverWindow(img, c, 0, 0, img.width, img.height);
}

// Mean Rec. 709 luminance of each 8x8 block (the unit per-block Welch tests compare).
inline std::vector<double> BlockLuminance(const FilmImage& img) {
  std::vector<double> blocks;
  for (int by = 0; by + 8 <= img.height; by += 8)
    for (int bx = 0; bx + 8 <= img.width; bx += 8) {
      double sum = 0.0;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) {
          const float* p = &img.rgb[3 * (size_t(y) * img.width + x)];
          sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
      blocks.push_back(sum / 64.0);
    }
  return blocks;
}

// z with P(|Z| > z) = p, by bisection on erfc (for Bonferroni splits of a false-alarm budget).
inline double TwoSidedNormalQuantile(double p) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Means over windows {x0, y0, x1, y1} of two independent renders agree: z on the difference
// with the films' variances, or within `relative` of the mean where the images are nearly
// noise-free (the backends' rounding differs). The call's windows x 3 comparisons share a
// false-alarm budget of 1e-4 (Bonferroni).
using Window = std::array<int, 4>;
inline void ExpectWindowsAgree(const FilmImage& a, const FilmImage& b,
                               const std::vector<Window>& windows, const char* what,
                               double relative = 0.0) {
  double z = TwoSidedNormalQuantile(1e-4 / (windows.size() * 3));
  for (size_t w = 0; w < windows.size(); ++w)
    for (int c = 0; c < 3; ++c) {
      const Window& r = windows[w];
      WindowMean ma = MeanOverWindow(a, c, r[0], r[1], r[2], r[3]);
      WindowMean mb = MeanOverWindow(b, c, r[0], r[1], r[2], r[3]);
      double tolerance = std::max(z * std::sqrt(ma.varianceOfMean + mb.varianceOfMean),
                                  relative * std::fabs(ma.mean));
      EXPECT_LE(std::abs(ma.mean - mb.mean), tolerance)
          << what << " window " << w << " channel " << c << ": " << ma.mean << " vs " << mb.mean;
    }
}

// The image cut into a grid of blocks x blocks windows.
inline std::vector<Window> BlockWindows(const FilmImage& img, int blocks) {
  std::vector<Window> windows;
  for (int by = 0; by < blocks; ++by)
    for (int bx = 0; bx < blocks; ++bx)
      windows.push_back({bx * img.width / blocks, by * img.height / blocks,
                         (bx + 1) * img.width / blocks, (by + 1) * img.height / blocks});
  return windows;
}


}  // namespace pt::test
