// The light samplers on the GPU: the CUDA backend renders the many-light room as the CPU
// backend does with each sampler (Welch's t per 8x8 block over independent seeds), and the
// bvh and power samplers agree with each other on the GPU too. Skips without a GPU.
#include <gtest/gtest.h>

#include "src/lights/light_bvh_build.h"
#include "tests/light_bvh_test_util.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {

FilmImage Render(bool gpu, LightSampler sampler, int seed) {
  Scene scene = SceneFromJson(ManyLightRoom(seed));
  RenderOptions o;
  o.lightSampler = sampler;
  RenderResult r = gpu ? RenderCuda(scene, o) : RenderOnCpu(scene, o);
  EXPECT_EQ(r.stats.lightSampler, LightSamplerName(sampler));
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  return r.image;
}

// Failing blocks at the 1% level between two renderers over 8 seeds each, against the count a
// Binomial(blocks, 0.01) exceeds with probability 1e-3.
void ExpectAgree(bool gpuA, LightSampler a, bool gpuB, LightSampler b) {
  const int kSeeds = 8;
  const double kBlockAlpha = 0.01;
  std::vector<std::vector<double>> x, y;
  for (int k = 0; k < kSeeds; ++k) {
    x.push_back(BlockLuminance(Render(gpuA, a, 300 + k)));
    y.push_back(BlockLuminance(Render(gpuB, b, 400 + k)));
  }
  int blocks = int(x[0].size()), failing = FailingBlocks(x, y, kBlockAlpha);
  EXPECT_LE(failing, BinomialUpperBound(blocks, kBlockAlpha, 1e-3))
      << (gpuA ? "gpu " : "cpu ") << LightSamplerName(a) << " vs " << (gpuB ? "gpu " : "cpu ")
      << LightSamplerName(b) << ": " << failing << " of " << blocks << " blocks differ";
}

TEST(LightBvhGpu, EverySamplerRendersAsOnTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  for (LightSampler s : {LightSampler::kBvh, LightSampler::kPower, LightSampler::kUniform})
    ExpectAgree(false, s, true, s);
}

TEST(LightBvhGpu, BvhAndPowerAgreeOnTheGpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  ExpectAgree(true, LightSampler::kBvh, true, LightSampler::kPower);
}

}  // namespace
}  // namespace pt::test
