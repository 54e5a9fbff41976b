// Adaptive sampling: converged pixels stop taking samples, the picture stays right, and the
// render stays deterministic.
#include <gtest/gtest.h>

#include <cstring>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

// Left half: the background seen directly (zero variance, converges at min_spp). Right half:
// a diffuse wall lit by a panel facing it, which every wall point sees (noisy, never
// zero-variance; a light most samples miss would let pixels "converge" on zeros, the known
// failure of variance-based stopping).
const char* kHalfAndHalf = R"({
  "render": {"width": 32, "height": 16, "spp": 128, "max_depth": 3, "seed": 5,
             "adaptive": {"tolerance": 0.02, "min_spp": 8, "batch": 8}},
  "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y": 40},
  "background": [1, 1, 1],
  "materials": {
    "panel": {"type": "emissive", "radiance": [20, 20, 20]},
    "wall": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}
  },
  "objects": [
    {"type": "quad", "origin": [0, -5, 0], "u": [5, 0, 0], "v": [0, 10, 0], "material": "wall"},
    {"type": "quad", "origin": [2.2, -0.3, 1], "u": [0, 0.6, 0], "v": [0.6, 0, 0],
     "material": "panel"}
  ]
})";

TEST(Adaptive, ConvergedPixelsStopAndImageStaysRight) {
  Scene scene = SceneFromJson(kHalfAndHalf);
  RenderResult adaptive = RenderOnCpu(scene);
  // The reference: every pixel at the full count, with another seed (independent estimates).
  SceneDesc desc = scene.desc;
  desc.render.seed = 99;
  RenderOptions off;
  off.adaptive = Toggle::kOff;
  RenderResult full = RenderOnCpu(BuildScene(desc), off);
  const FilmImage& a = adaptive.image;
  // The background half stops at min_spp: its luminance variance is exactly 0.
  EXPECT_EQ(a.samples[8 * 32 + 4], 8u);
  // The lit wall keeps sampling: more than min_spp at its noisiest pixels.
  uint32_t most = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 17; x < 26; ++x) most = std::max(most, a.samples[y * 32 + x]);
  EXPECT_GT(most, 8u);
  EXPECT_LT(adaptive.stats.sppMean, 128.0);
  EXPECT_EQ(adaptive.stats.samples, uint64_t(adaptive.stats.sppMean * 32 * 16 + 0.5));
  // Same picture in the mean: the wall half's mean luminance over both renders, with the
  // films' variances; z = 3.89 (two-sided false alarm 1e-4).
  WindowMean ma = MeanOverWindow(a, 1, 17, 0, 26, 16);
  WindowMean mf = MeanOverWindow(full.image, 1, 17, 0, 26, 16);
  EXPECT_LT(std::abs(ma.mean - mf.mean), kZ1e4 * std::sqrt(ma.varianceOfMean + mf.varianceOfMean));
  EXPECT_NEAR(a.rgb[3 * (8 * 32 + 4)], 1.0f, 1e-6f);
}

TEST(Adaptive, DeterministicAcrossThreadsAndCompaction) {
  Scene scene = SceneFromJson(kHalfAndHalf);
  RenderOptions one;
  one.threads = 1;
  one.compact = Toggle::kOff;
  RenderOptions two;
  two.threads = 2;
  two.maxPathsInFlight = 1000;  // several waves per batch
  FilmImage a = RenderCpu(scene, one).image, b = RenderCpu(scene, two).image;
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_EQ(0, std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)));
}

}  // namespace
}  // namespace pt::test
