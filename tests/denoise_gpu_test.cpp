// The denoiser's passes on the GPU agree with the CPU's within float rounding (the GPU fuses
// multiply-adds; every pass is otherwise the same arithmetic): on a synthetic film and on a
// rendered one (glass, mirror and diffuse surfaces). Skip without a GPU.
#include <gtest/gtest.h>

#include <cmath>

#include "src/denoise/denoiser.h"
#include "tests/denoise_test_util.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

void ExpectCpuGpuAgree(const FilmImage& img, const DenoiseSettings& settings = {}) {
  FilmImage cpu = img, gpu = img;
  MakeCpuDenoiser(2, settings)->Denoise(cpu);
  MakeCudaDenoiser(0, settings)->Denoise(gpu);
  ASSERT_EQ(cpu.denoised.size(), gpu.denoised.size());
  double worst = 0.0;
  for (size_t i = 0; i < cpu.denoised.size(); ++i) {
    double a = cpu.denoised[i], b = gpu.denoised[i];
    ASSERT_TRUE(std::isfinite(b)) << i;
    worst = std::max(worst, std::fabs(a - b) / (1e-3 + std::fabs(a)));
  }
  // A weight exp(-d) moves by d * 1e-7 relative when d does; d up to 30 (then 0).
  EXPECT_LT(worst, 2e-4) << "the largest relative difference";
}

TEST(DenoiseGpu, SyntheticFilmMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  FilmImage img = SyntheticImage(97, 61, 16, [](int x, int y) {
    SyntheticPixel p;
    float a = (x / 8 + y / 8) % 2 ? 0.7f : 0.2f;
    p.albedo = vec3(a, 0.5f, 1.0f - a);
    p.color = p.albedo * (0.5f + 0.01f * float(x));
    p.normal = glm::normalize(vec3(0.1f * float(x % 5), 0.0f, 1.0f));
    p.depth = 2.0f + 0.05f * float(y);
    p.sigma = 0.3f;
    return p;
  }, 9);
  // Fireflies, so that the outlier passes scale some pixels (nlm_outliers.h).
  for (int k = 0; k < 12; ++k) AddFirefly(img, (k * 37) % 97, (k * 23) % 61, 200.0f + 50.0f * k);
  ExpectCpuGpuAgree(img);
}

TEST(DenoiseGpu, RenderedFilmMatchesTheCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  SceneDesc d = LoadScene(SourcePath("scenes/cornell_glass_mirror.json"));
  d.render.width = d.render.height = 64;
  d.render.spp = 8;
  Scene scene = BuildScene(std::move(d));
  RenderOptions o;
  o.featureBuffers = o.halfFilms = true;
  FilmImage film = RenderOnCpu(scene, o).image;
  ExpectCpuGpuAgree(film);
  DenoiseSettings keep;  // the residual filtered, the seen emission (the light) added back
  keep.keepSeenEmission = true;
  ExpectCpuGpuAgree(film, keep);
}

}  // namespace
}  // namespace pt::test
