// The CUDA backend gives the CPU backend's answer: for every scene in scenes/, K independent
// seeds per backend, Welch's t per 8x8 block of luminance, and no more failing blocks than a
// binomial bound allows. GPU cases skip (with a message) where no GPU is present.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "src/integrator/render_session.h"
#include "src/integrator/wave_plan.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {

SceneDesc SeededSceneDesc(const std::string& file, int size, int spp, uint32_t seed) {
  SceneDesc desc = LoadScene(file);
  desc.render.width = desc.render.height = size;
  desc.render.spp = spp;
  desc.render.seed = seed;
  return desc;
}


TEST(BackendAgreementGpu, EveryProjectSceneAgreesWithCpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here: the CPU/GPU agreement runs on a GPU machine";
  const int kSeeds = 8, kSize = 64, kSpp = 16;
  const double kBlockAlpha = 0.01;  // per-block test level
  for (const auto& entry : std::filesystem::directory_iterator(SourcePath("scenes"))) {
    if (entry.path().extension() != ".json") continue;
    std::vector<std::vector<double>> cpu, gpu;  // [seed][block]
    for (int k = 0; k < kSeeds; ++k) {
      Scene a = BuildScene(SeededSceneDesc(entry.path().string(), kSize, kSpp, 1000 + k));
      Scene b = BuildScene(SeededSceneDesc(entry.path().string(), kSize, kSpp, 2000 + k));
      cpu.push_back(BlockLuminance(RenderOnCpu(a).image));
      gpu.push_back(BlockLuminance(RenderCuda(b, RenderOptions{}).image));
    }
    int blocks = int(cpu[0].size()), failing = FailingBlocks(cpu, gpu, kBlockAlpha);
    // Under agreement, failing ~ Binomial(blocks, 0.01); the bound's tail is 1e-3 per scene.
    int bound = BinomialUpperBound(blocks, kBlockAlpha, 1e-3);
    EXPECT_LE(failing, bound) << entry.path().filename() << ": " << failing << " of " << blocks
                              << " blocks differ at the 1% level";
  }
}

// On the GPU too, compaction and sorting reorder work but not results: every path runs the
// same code on the same random numbers, so the image is bit-identical.
TEST(BackendAgreementGpu, CompactionAndSortDoNotChangeTheGpuImage) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene =
      BuildScene(SeededSceneDesc(SourcePath("scenes/cornell_glass_mirror.json"), 64, 8, 5));
  RenderOptions base;
  base.compact = Toggle::kOff;
  base.sort = SortMode::kOff;
  RenderResult ref = RenderCuda(scene, base);
  for (auto [compact, sort] : {std::pair{Toggle::kOn, SortMode::kOff},
                               std::pair{Toggle::kOn, SortMode::kMaterial},
                               std::pair{Toggle::kOff, SortMode::kMaterial}}) {
    RenderOptions opt;
    opt.compact = compact;
    opt.sort = sort;
    RenderResult r = RenderCuda(scene, opt);
    EXPECT_TRUE(SameImage(ref.image, r.image))
        << "compact " << int(compact) << " sort " << int(sort);
  }
}

// --ray-order on the GPU (the CPU's case is in sort_modes_test.cpp): the same image, with and
// without compaction and with shading sorted by material.
TEST(BackendAgreementGpu, RayOrderDoesNotChangeTheImage) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene =
      BuildScene(SeededSceneDesc(SourcePath("scenes/cornell_glass_mirror.json"), 64, 4, 7));
  for (auto [compact, sort] : {std::pair{Toggle::kOn, SortMode::kOff},
                               std::pair{Toggle::kOff, SortMode::kOff},
                               std::pair{Toggle::kOn, SortMode::kMaterial}}) {
    RenderOptions off, on;
    off.compact = on.compact = compact;
    off.sort = on.sort = sort;
    off.rayOrder = Toggle::kOff;
    on.rayOrder = Toggle::kOn;
    RenderResult a = RenderCuda(scene, off), b = RenderCuda(scene, on);
    EXPECT_FALSE(a.stats.rayOrderUsed);
    EXPECT_TRUE(b.stats.rayOrderUsed);
    EXPECT_TRUE(SameImage(a.image, b.image))
        << "compact " << int(compact) << ", sort " << int(sort);
    EXPECT_EQ(a.stats.nodesVisited, b.stats.nodesVisited);
  }
}

// --warm-up on the GPU: the discarded wave that loads the kernels (auto: on under CUDA's
// default lazy loading) leaves the image and the traversal work as they are without it.
TEST(BackendAgreementGpu, WarmUpDoesNotChangeTheImage) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene =
      BuildScene(SeededSceneDesc(SourcePath("scenes/cornell_glass_mirror.json"), 64, 4, 7));
  RenderOptions off, on, automatic;
  off.warmUp = Toggle::kOff;
  on.warmUp = Toggle::kOn;
  RenderResult a = RenderCuda(scene, off), b = RenderCuda(scene, on);
  EXPECT_FALSE(a.stats.warmedUp);
  EXPECT_TRUE(b.stats.warmedUp);
  EXPECT_GT(b.stats.warmUpMs, 0.0);
  EXPECT_TRUE(SameImage(a.image, b.image));
  EXPECT_EQ(a.stats.nodesVisited, b.stats.nodesVisited);
  EXPECT_EQ(a.stats.shadowRays, b.stats.shadowRays);
  const char* mode = std::getenv("CUDA_MODULE_LOADING");
  EXPECT_EQ(RenderCuda(scene, automatic).stats.warmedUp,
            mode == nullptr || std::string(mode) != "EAGER");
}

// The image the GPU resolves from its film (ResolveFilmPixel, in doubles) is the one the host
// resolves from the downloaded film (ResolveFilmImage), float for float, with the feature and
// half-film channels of a --denoise render.
TEST(BackendAgreementGpu, TheResolvedImageIsTheSavedFilmsResolved) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene =
      BuildScene(SeededSceneDesc(SourcePath("scenes/cornell_glass_mirror.json"), 64, 3, 7));
  for (bool dbl : {false, true}) {
    RenderOptions o;
    o.filmDouble = dbl;
    o.featureBuffers = o.halfFilms = true;
    auto session = MakeCudaSession(scene, o);
    session->RenderRange(0, 3);
    const FilmImage device = session->Image();
    const FilmImage host = ResolveFilmImage(session->SaveFilm());
    EXPECT_TRUE(BitIdentical(device.rgb, host.rgb)) << dbl;
    EXPECT_TRUE(BitIdentical(device.variance, host.variance)) << dbl;
    EXPECT_TRUE(BitIdentical(device.albedo, host.albedo)) << dbl;
    EXPECT_TRUE(BitIdentical(device.normal, host.normal)) << dbl;
    EXPECT_TRUE(BitIdentical(device.depth, host.depth)) << dbl;
    EXPECT_TRUE(BitIdentical(device.evenRgb, host.evenRgb)) << dbl;
    EXPECT_EQ(device.samples, host.samples);
    EXPECT_EQ(device.evenSamples, host.evenSamples);
  }
}

// --prim-pool on the GPU: the lanes of a warp test each other's leaf primitives, and the
// closest hit is still the smallest (t, tagIndex), so the image is the per-ray walk's. Both
// kernel variants: without the hit test, and with it (--tri-test box-clamped runs those).
TEST(BackendAgreementGpu, PrimPoolDoesNotChangeTheImage) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  BvhBuildOptions wide;
  wide.layout = BvhLayout::kWide;
  Scene scene =
      BuildScene(SeededSceneDesc(SourcePath("scenes/mesh_scene.json"), 64, 4, 5), wide);
  for (TriangleTest test : {TriangleTest::kWatertight, TriangleTest::kBoxClamped}) {
    for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
      RenderOptions off, on;
      off.compact = on.compact = compact;
      off.triangleTest = on.triangleTest = test;
      off.primPool = Toggle::kOff;
      on.primPool = Toggle::kOn;
      RenderResult a = RenderCuda(scene, off), b = RenderCuda(scene, on);
      EXPECT_FALSE(a.stats.primPoolUsed);
      EXPECT_TRUE(b.stats.primPoolUsed);
      EXPECT_GT(b.stats.primsTested, 0u);
      EXPECT_EQ(a.stats.shadowRays, b.stats.shadowRays);
      EXPECT_TRUE(SameImage(a.image, b.image))
          << "tri-test " << int(test) << ", compact " << int(compact);
    }
  }
}

// Values of b that differ from a's by more than a relative 1e-4 (count).
size_t DifferingValues(const FilmImage& a, const FilmImage& b) {
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    const float x = a.rgb[i], y = b.rgb[i];
    if (!(std::fabs(x - y) <= 1e-4f * std::max(std::fabs(x), std::fabs(y)))) ++differ;
  }
  return differ;
}

// The closest hit does not depend on the tree or the order of its walk (the GPU's wide
// closest-hit walks take each node's nearest child first; the binary one the nearer child;
// pooled walks test leaves in rounds): with --tri-test box-clamped, which removes the
// coincident-surface exception (docs/bvh.md), the layouts render the same image on the GPU,
// flat and instanced. Up to rounding: the kernels inline the shape tests with their own fused
// multiply-adds, so a hit may move by an ulp; a walk that lost a child would differ in many
// pixels.
TEST(BackendAgreementGpu, LayoutsRenderTheSameImage) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  for (const char* file : {"scenes/mesh_scene.json", "scenes/instanced_shapes.json",
                           "scenes/cornell_glass_mirror.json"}) {
    const SceneDesc desc = SeededSceneDesc(SourcePath(file), 64, 4, 9);
    BvhBuildOptions binary, wide;
    binary.layout = BvhLayout::kBinary;
    wide.layout = BvhLayout::kWide;
    const Scene a = BuildScene(desc, binary), b = BuildScene(desc, wide);
    RenderOptions perRay, pooled;
    perRay.triangleTest = pooled.triangleTest = TriangleTest::kBoxClamped;
    perRay.primPool = Toggle::kOff;
    pooled.primPool = Toggle::kOn;
    const FilmImage ref = RenderCuda(a, perRay).image;
    for (const RenderOptions& options : {perRay, pooled}) {
      const FilmImage image = RenderCuda(b, options).image;
      ASSERT_EQ(image.rgb.size(), ref.rgb.size());
      EXPECT_LE(DifferingValues(ref, image), ref.rgb.size() / 1000)
          << file << ", prim-pool " << int(options.primPool);
    }
  }
}

TEST(BackendAgreementGpu, StatisticsAreFilledOnTheGpu) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  Scene scene = BuildScene(SeededSceneDesc(SourcePath("scenes/cornell_box.json"), 64, 4, 1));
  RenderResult r = RenderCuda(scene, RenderOptions{});
  EXPECT_EQ(r.stats.backend, "cuda");
  EXPECT_FALSE(r.stats.device.empty());
  EXPECT_GT(r.stats.stages.intersect, 0.0);
  EXPECT_GT(r.stats.stages.shade, 0.0);
  EXPECT_GT(r.stats.peakDeviceBytes, 0u);
  EXPECT_EQ(r.stats.cameraRays, 64u * 64u * 4u);
  EXPECT_GT(r.stats.shadowRays, 0u);
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
}

}  // namespace
}  // namespace pt::test
