// The light-transport features run on the GPU through the same stage bodies and agree with
// the CPU: textures, adaptive sampling, --light-paths, the feature buffers, spot and
// directional lights. (GGX, plastic and depth of field are covered by the per-scene agreement
// test over scenes/.) Skip without a GPU.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/texture_test_util.h"

namespace pt::test {
namespace {

Scene CornellSmall(uint32_t seed, int spp) {
  SceneDesc d = LoadScene(SourcePath("scenes/cornell_glass_mirror.json"));
  d.render.width = d.render.height = 48;
  d.render.spp = spp;
  d.render.seed = seed;
  return BuildScene(std::move(d));
}

TEST(FeatureAgreementGpu, TexturedCheckerMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  RgbaImage png(8, 8);
  const uint8_t blocks[4][3] = {{255, 128, 0}, {0, 255, 64}, {64, 0, 255}, {200, 200, 200}};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const uint8_t* c = blocks[(y / 4) * 2 + x / 4];
      png.Set(x, y, c[0], c[1], c[2], 255);
    }
  std::string dir = TempDir();
  WriteTexturedSquareGltf(dir, png, 33071, 33071);
  double fov = 2.0 * std::atan(1.0 / 4.0) * 180.0 / M_PI;
  auto scene = [&](uint32_t seed) {
    std::string json = R"({"render": {"width": 32, "height": 32, "spp": 64, "max_depth": 2, "seed": )" +
                       std::to_string(seed) + R"(}, "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y": )" +
                       std::to_string(fov) + R"(}, "background": [1, 1, 1], "materials": {},
        "objects": [{"type": "mesh", "file": "square.gltf"}]})";
    return BuildScene(LoadSceneFromString(json, "checker.json", dir));
  };
  FilmImage cpu = RenderOnCpu(scene(1)).image, gpu = RenderCuda(scene(2), {}).image;
  std::vector<Window> windows = {
      {2, 2, 11, 11}, {21, 2, 30, 11}, {2, 21, 11, 30}, {21, 21, 30, 30}};
  ExpectWindowsAgree(cpu, gpu, windows, "texture quadrant");
}

TEST(FeatureAgreementGpu, AdaptiveSamplingMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene a = CornellSmall(21, 64), b = CornellSmall(22, 64);
  RenderOptions opt;
  opt.adaptive = Toggle::kOn;  // the scene has no settings: defaults (0.05, 16, 16)
  RenderResult cpu = RenderOnCpu(a, opt), gpu = RenderCuda(b, opt);
  EXPECT_LT(gpu.stats.sppMean, 64.0);  // some pixels converged on the GPU too
  EXPECT_NEAR(gpu.stats.sppMean, cpu.stats.sppMean, 0.1 * cpu.stats.sppMean);
  ExpectWindowsAgree(cpu.image, gpu.image, BlockWindows(cpu.image, 2), "adaptive quadrant");
}

// Same seed, same kernels: direct and indirect split the GPU's own paths exactly.
TEST(FeatureAgreementGpu, LightPathsSplitOnTheGpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene = CornellSmall(5, 8);
  RenderOptions opt;
  FilmImage all = RenderCuda(scene, opt).image;
  opt.lightPaths = LightPaths::kDirect;
  FilmImage direct = RenderCuda(scene, opt).image;
  opt.lightPaths = LightPaths::kIndirect;
  FilmImage indirect = RenderCuda(scene, opt).image;
  for (size_t i = 0; i < all.rgb.size(); ++i)
    ASSERT_NEAR(direct.rgb[i] + indirect.rgb[i], all.rgb[i], 1e-4f * std::max(1.0f, all.rgb[i]));
}

TEST(FeatureAgreementGpu, FeatureBuffersMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene = CornellSmall(3, 4);
  RenderOptions opt;
  opt.featureBuffers = true;
  FilmImage cpu = RenderOnCpu(scene, opt).image, gpu = RenderCuda(scene, opt).image;
  ASSERT_EQ(gpu.albedo.size(), cpu.albedo.size());
  // Same camera jitter on both backends: first hits agree except where FMA rounding tips a
  // sample across an edge; the image means agree to 1%.
  double ca = 0, ga = 0, cd = 0, gd = 0;
  for (size_t i = 0; i < cpu.albedo.size(); ++i) ca += cpu.albedo[i], ga += gpu.albedo[i];
  for (size_t i = 0; i < cpu.depth.size(); ++i) cd += cpu.depth[i], gd += gpu.depth[i];
  EXPECT_NEAR(ga, ca, 0.01 * ca);
  EXPECT_NEAR(gd, cd, 0.01 * cd);
}

// With half films (--denoise) the GPU's film holds the seen emission's means and the
// residual's variance as the CPU's does: the same camera jitter, so the emission (the light
// and what the mirror shows of it is not in it: depth 0 only) agrees to 1% over the image, and
// the residual's variance, of the paths themselves, to 5%.
TEST(FeatureAgreementGpu, HalfFilmsMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene = CornellSmall(4, 16);
  RenderOptions opt;
  opt.featureBuffers = opt.halfFilms = true;
  FilmImage cpu = RenderOnCpu(scene, opt).image, gpu = RenderCuda(scene, opt).image;
  auto sum = [](const std::vector<float>& v) {
    double s = 0.0;
    for (float x : v) s += x;
    return s;
  };
  ASSERT_EQ(gpu.emission.size(), cpu.rgb.size());
  ASSERT_EQ(gpu.residualVariance.size(), cpu.rgb.size());
  EXPECT_GT(sum(cpu.emission), 0.0);  // the camera sees the light
  EXPECT_NEAR(sum(gpu.emission), sum(cpu.emission), 0.01 * sum(cpu.emission));
  EXPECT_NEAR(sum(gpu.evenEmission), sum(cpu.evenEmission), 0.01 * sum(cpu.evenEmission));
  EXPECT_NEAR(sum(gpu.residualVariance), sum(cpu.residualVariance),
              0.05 * sum(cpu.residualVariance));
}

// Spot (inside, between and outside its cones) and directional lights over a diffuse floor
// with a box casting shadows and bouncing light: the GPU's image agrees with the CPU's.
TEST(FeatureAgreementGpu, SpotAndDirectionalLightsMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  auto scene = [](uint32_t seed) {
    std::string json = R"({"render": {"width": 48, "height": 48, "spp": 64, "max_depth": 3, "seed": )" +
                       std::to_string(seed) + R"(}, "camera": {"position": [0, 8, 0.01], "look_at": [0, 0, 0],
        "fov_y": 60}, "materials": {"m": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
        "objects": [{"type": "quad", "origin": [-6, 0, -6], "u": [0, 0, 12], "v": [12, 0, 0], "material": "m"},
                    {"type": "box", "min": [1, 0, 1], "max": [2.5, 1.5, 2.5], "material": "m"}],
        "lights": [{"type": "spot", "position": [-1, 3, -1], "direction": [0, -1, 0],
                    "intensity": [20, 10, 5], "inner_angle": 20, "outer_angle": 45},
                   {"type": "directional", "direction": [-1, -2, -0.5], "irradiance": [0.5, 0.6, 0.8]}]})";
    return BuildScene(LoadSceneFromString(json, "spot_sun.json", "."));
  };
  FilmImage cpu = RenderOnCpu(scene(1)).image, gpu = RenderCuda(scene(2), {}).image;
  std::vector<Window> windows = {{14, 14, 22, 22}, {4, 4, 12, 12}, {30, 30, 40, 40}, {36, 4, 46, 14}};
  ExpectWindowsAgree(cpu, gpu, windows, "spot/directional window");
}

}  // namespace
}  // namespace pt::test
