// --sampler sobol in whole renders: it estimates the image independent numbers estimate
// (Welch's t per 8x8 block over seeds), with less noise where a pixel's coverage dominates
// (emitters' edges seen directly), and a crop renders the full image's pixels (the same image
// for any thread count, compaction, sort or wave size: tests/determinism_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {

RenderOptions SamplerOptions(SamplerKind sampler, int threads = 2) {
  RenderOptions o;
  o.sampler = sampler;
  o.threads = threads;
  return o;
}

Scene BoxWithSeed(uint32_t seed, int size, int spp, int maxDepth) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_box.json"));
  desc.render.width = desc.render.height = size;
  desc.render.spp = spp;
  desc.render.maxDepth = maxDepth;
  desc.render.seed = seed;
  return BuildScene(std::move(desc));
}

// Under agreement each block fails at the 1% level with probability 0.01; the count allowed
// is exceeded with probability 1e-3.
TEST(SobolRender, SobolAndIndependentEstimateTheSameImage) {
  const int kSeeds = 6;
  const double kBlockAlpha = 0.01;
  std::vector<std::vector<double>> sobol, independent;
  for (int k = 0; k < kSeeds; ++k) {
    RenderResult s = RenderCpu(BoxWithSeed(100 + k, 64, 8, 8), SamplerOptions(SamplerKind::kSobol));
    EXPECT_EQ(s.stats.sampler, "sobol");
    EXPECT_EQ(s.stats.nonfiniteSamples, 0u);
    sobol.push_back(BlockLuminance(s.image));
    RenderResult i =
        RenderCpu(BoxWithSeed(200 + k, 64, 8, 8), SamplerOptions(SamplerKind::kIndependent));
    EXPECT_EQ(i.stats.sampler, "independent");
    independent.push_back(BlockLuminance(i.image));
  }
  int blocks = int(sobol[0].size()), failing = FailingBlocks(sobol, independent, kBlockAlpha);
  EXPECT_LE(failing, BinomialUpperBound(blocks, kBlockAlpha, 1e-3))
      << failing << " of " << blocks << " blocks differ at the 1% level";
}

// Emissive spheres and an oblique emissive quad on black, seen directly (max depth 0): the
// only noise is each pixel's coverage, which the camera pair's net stratifies.
std::string EdgesScene(uint32_t seed, int spp) {
  return R"({
    "render": {"width": 64, "height": 64, "spp": )" + std::to_string(spp) +
         R"(, "max_depth": 0, "seed": )" + std::to_string(seed) + R"(},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
    "background": [0, 0, 0],
    "materials": {"lamp": {"type": "emissive", "radiance": [1, 1, 1]}},
    "objects": [
      {"type": "sphere", "center": [-0.6, 0.6, 0], "radius": 0.3, "material": "lamp"},
      {"type": "sphere", "center": [0.7, 0.5, 0], "radius": 0.15, "material": "lamp"},
      {"type": "sphere", "center": [0.0, -0.1, 0], "radius": 0.22, "material": "lamp"},
      {"type": "quad", "origin": [-0.9, -0.9, 0], "u": [0.8, 0.25, 0], "v": [-0.2, 0.5, 0],
       "material": "lamp"}]})";
}

// Sum over pixels of the variance across seeds of the pixel's luminance (each seed an
// independent estimate), and that sum's standard error (pixels independent).
struct PixelVariance {
  double sum = 0.0, standardError = 0.0;
};

PixelVariance VarianceAcrossSeeds(const std::vector<FilmImage>& images) {
  const size_t n = images.size(), pixels = images[0].samples.size();
  PixelVariance v;
  double varOfSum = 0.0;
  for (size_t p = 0; p < pixels; ++p) {
    std::vector<double> l;
    double mean = 0.0;
    for (const FilmImage& img : images) {
      const float* c = &img.rgb[3 * p];
      l.push_back(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]);
      mean += l.back() / n;
    }
    double s2 = 0.0, m4 = 0.0;
    for (double x : l) s2 += (x - mean) * (x - mean), m4 += std::pow(x - mean, 4);
    s2 /= n - 1;
    m4 /= n;
    v.sum += s2;
    // Var(s^2) ~ (m4 - s^4 (n - 3) / (n - 1)) / n.
    varOfSum += std::max(0.0, (m4 - s2 * s2 * (n - 3.0) / (n - 1.0)) / n);
  }
  v.standardError = std::sqrt(varOfSum);
  return v;
}

PixelVariance EdgeVariance(SamplerKind sampler, int spp) {
  std::vector<FilmImage> images;
  for (uint32_t seed = 1; seed <= 12; ++seed)
    images.push_back(
        RenderCpu(SceneFromJson(EdgesScene(seed, spp)), SamplerOptions(sampler)).image);
  return VarianceAcrossSeeds(images);
}

// A jittered (0,2)-net puts a straight edge's coverage error at O(n^-3/4) against Monte
// Carlo's n^-1/2: at 16 spp about a quarter of the variance. The test asks for less than
// half, with four standard errors of both estimates to spare.
TEST(SobolRender, LessNoiseWherePixelCoverageDominates) {
  const int kSpp = 16;
  PixelVariance sobol = EdgeVariance(SamplerKind::kSobol, kSpp);
  PixelVariance independent = EdgeVariance(SamplerKind::kIndependent, kSpp);
  ASSERT_GT(independent.sum, 0.0);
  const double kMaxRatio = 0.5;
  EXPECT_LT(sobol.sum + 4.0 * sobol.standardError,
            kMaxRatio * (independent.sum - 4.0 * independent.standardError))
      << "summed pixel variance: sobol " << sobol.sum << " +- " << sobol.standardError
      << ", independent " << independent.sum << " +- " << independent.standardError
      << " (ratio " << sobol.sum / independent.sum << ")";
}

TEST(SobolRender, ACropRendersTheFullImagesPixels) {
  Scene scene = SmallScene(SourcePath("scenes/cornell_box.json"), 48, 40, 4);
  RenderResult full = RenderCpu(scene, SamplerOptions(SamplerKind::kSobol));
  RenderOptions o = SamplerOptions(SamplerKind::kSobol);
  o.crop = CropWindow{11, 7, 30, 33};
  RenderResult crop = RenderCpu(scene, o);
  ASSERT_EQ(crop.image.width, 19);
  ASSERT_EQ(crop.image.height, 26);
  int mismatches = 0;
  for (int y = 0; y < crop.image.height; ++y)
    for (int x = 0; x < crop.image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float a = crop.image.rgb[3 * (size_t(y) * crop.image.width + x) + c];
        float b = full.image.rgb[3 * (size_t(y + 7) * full.image.width + x + 11) + c];
        if (std::memcmp(&a, &b, sizeof(float)) != 0) ++mismatches;
      }
  EXPECT_EQ(mismatches, 0);
}

// The scene's render block may ask for the sampler; an option given overrides it.
TEST(SobolRender, TheSceneFileCanAskForSobolAndTheOptionOverridesIt) {
  const std::string json = EdgesScene(3, 4);
  auto withSampler = [&](const std::string& name) {
    std::string text = json;
    return text.replace(text.find("\"seed\""), 6, "\"sampler\": \"" + name + "\", \"seed\"");
  };
  Scene plain = SceneFromJson(json), sobol = SceneFromJson(withSampler("sobol"));
  EXPECT_EQ(plain.desc.render.sampler, SamplerKind::kIndependent);
  ASSERT_EQ(sobol.desc.render.sampler, SamplerKind::kSobol);
  RenderResult fromScene = RenderOnCpu(sobol);
  EXPECT_EQ(fromScene.stats.sampler, "sobol");
  EXPECT_TRUE(
      SameImage(fromScene.image, RenderOnCpu(plain, SamplerOptions(SamplerKind::kSobol)).image));
  RenderResult overridden = RenderOnCpu(sobol, SamplerOptions(SamplerKind::kIndependent));
  EXPECT_EQ(overridden.stats.sampler, "independent");
  EXPECT_TRUE(SameImage(overridden.image, RenderOnCpu(plain).image));
  EXPECT_FALSE(SameImage(overridden.image, fromScene.image));
  try {
    SceneFromJson(withSampler("halton"));
    ADD_FAILURE() << "an unknown sampler was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'halton' is not a sampler"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pt::test
