// Helpers for tests that render whole scenes: load from inline JSON, render on a backend,
// and compare images statistically with tolerances derived from the film's own variance.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "src/integrator/render_api.h"
#include "src/io/scene_loader.h"

namespace pt::test {

inline Scene SceneFromJson(const std::string& json) {
  return BuildScene(LoadSceneFromString(json, "inline-test-scene.json", "."));
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

// z with P(|Z| > z) = p, by bisection on erfc (for Bonferroni splits of a false-alarm budget).
inline double TwoSidedNormalQuantile(double p) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Means over windows of two independent renders agree: z on the difference with the films'
// variances, or within `relative` of the mean where the images are nearly noise-free (the
// backends' rounding differs). The call's count x 3 comparisons share a false-alarm budget of
// 1e-4 (Bonferroni). Windows are {x0, y0, x1, y1}.
inline void ExpectWindowsAgree(const FilmImage& a, const FilmImage& b, const int windows[][4],
                               int count, const char* what, double relative = 0.0) {
  double z = TwoSidedNormalQuantile(1e-4 / (count * 3));
  for (int w = 0; w < count; ++w)
    for (int c = 0; c < 3; ++c) {
      const int* r = windows[w];
      WindowMean ma = MeanOverWindow(a, c, r[0], r[1], r[2], r[3]);
      WindowMean mb = MeanOverWindow(b, c, r[0], r[1], r[2], r[3]);
      double tolerance = std::max(z * std::sqrt(ma.varianceOfMean + mb.varianceOfMean),
                                  relative * std::fabs(ma.mean));
      EXPECT_LE(std::abs(ma.mean - mb.mean), tolerance)
          << what << " window " << w << " channel " << c << ": " << ma.mean << " vs " << mb.mean;
    }
}

// Two-sided normal quantiles: z such that P(|Z| > z) = p.
constexpr double kZ1e4 = 3.8906;   // p = 1e-4
constexpr double kZ1e5 = 4.4172;   // p = 1e-5

}  // namespace pt::test
