// The live preview's denoise option: display only (the accumulation goes on), frames then
// carry the denoised layer and its time; refused where the preview has no denoiser.
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

#include "src/denoise/denoiser.h"
#include "src/io/scene_loader.h"
#include "src/server/live_render.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

std::unique_ptr<LiveRender> LiveBox(bool withDenoiser,
                                    std::function<DenoiseSettings(SamplerKind)> bySampler = {}) {
  std::string path = SourcePath("scenes/cornell_box.json");
  SceneDesc desc = LoadScene(path);
  desc.render.width = desc.render.height = 24;
  desc.render.spp = 64;
  SceneDocument document(path, desc.render);
  LiveSettings settings;
  settings.options.threads = 2;
  settings.framesPerSecond = 50;
  if (withDenoiser) settings.makeDenoiser = [] { return MakeCpuDenoiser(2); };
  settings.denoiseSettings = std::move(bySampler);
  return std::make_unique<LiveRender>(std::move(document), BuildScene(std::move(desc)),
                                      &MakeCpuSession, settings);
}

TEST(DenoiseServe, TheToggleDenoisesFramesWithoutRestarting) {
  std::unique_ptr<LiveRender> live = LiveBox(true);
  auto frame = live->WaitForFrame(0, std::chrono::seconds(20));
  ASSERT_TRUE(frame);
  uint64_t generation = live->EditOptions(Json{{"denoise", true}}).generation;
  EXPECT_EQ(generation, frame->generation);  // nothing restarts
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::shared_ptr<const FilmImage> image;
  while (std::chrono::steady_clock::now() < deadline) {
    frame = live->WaitForFrame(frame->id, std::chrono::seconds(2));
    image = live->LatestImage();
    if (image && !image->denoised.empty() &&
        Json::parse(frame->statsJson).contains("denoise_ms"))
      break;
  }
  ASSERT_TRUE(image);
  EXPECT_EQ(image->denoised.size(), image->rgb.size());
  EXPECT_TRUE(Json::parse(live->DescribeJson())["options"]["denoise"].get<bool>());
  EXPECT_THROW(live->EditOptions(Json{{"denoise", "yes"}}), EditError);
  live->Stop();
}

// The toggle is part of the one state every page follows: announced on the feed with the new
// value in it; after Stop the saved image carries the denoised layer it showed.
TEST(DenoiseServe, TheToggleIsPushedAndSaved) {
  std::unique_ptr<LiveRender> live = LiveBox(true);
  ASSERT_TRUE(live->WaitForFrame(0, std::chrono::seconds(20)));
  EXPECT_FALSE(Json::parse(live->StateJson())["options"]["denoise"].get<bool>());
  ChangeFeed::Versions before = live->Feed().Current();
  live->EditOptions(Json{{"denoise", true}});
  ChangeFeed::Versions after = live->Feed().Current();
  EXPECT_GT(after[ChangeFeed::kState], before[ChangeFeed::kState]);
  EXPECT_TRUE(Json::parse(live->StateJson())["options"]["denoise"].get<bool>());
  EXPECT_TRUE(live->Denoising());
  live->Stop();
  uint32_t spp = 0;
  std::shared_ptr<const FilmImage> image = live->FinalImage(&spp);
  ASSERT_TRUE(image);
  EXPECT_GT(spp, 0u);
  EXPECT_EQ(image->denoised.size(), image->rgb.size());
}

// The variance rule follows the page's sampler flag as the CLI's default does (sample variance
// for independent samples, calibrated for Sobol), and so does whatever else the per-sampler
// table sets (here the seen emission kept out for Sobol): each frame names what it was
// denoised with.
TEST(DenoiseServe, TheVarianceRuleFollowsTheSamplerFlag) {
  std::unique_ptr<LiveRender> live = LiveBox(true, [](SamplerKind sampler) {
    DenoiseSettings s;
    s.calibrateVariance = s.keepSeenEmission = sampler != SamplerKind::kIndependent;
    return s;
  });
  auto frame = live->WaitForFrame(0, std::chrono::seconds(20));
  ASSERT_TRUE(frame);
  live->EditOptions(Json{{"denoise", true}});
  // The first denoised frame of the generation in force after the edit (or none in 20 s).
  auto denoisedFrame = [&](uint64_t generation) -> Json {
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
      frame = live->WaitForFrame(frame->id, std::chrono::seconds(2));
      if (!frame || frame->generation < generation) continue;
      Json stats = Json::parse(frame->statsJson);
      if (stats.contains("denoise_variance")) return stats;
    }
    return Json();
  };
  Json before = denoisedFrame(frame->generation);
  ASSERT_TRUE(before.is_object());
  EXPECT_EQ(before["denoise_variance"], "sample");
  EXPECT_EQ(before["denoise_emission"], "filter");
  uint64_t generation = live->EditOptions(Json{{"sampler", "sobol"}}).generation;
  Json after = denoisedFrame(generation);
  ASSERT_TRUE(after.is_object());
  EXPECT_EQ(after["sampler"], "sobol");
  EXPECT_EQ(after["denoise_variance"], "calibrated");
  EXPECT_EQ(after["denoise_emission"], "keep");
  live->Stop();
}

TEST(DenoiseServe, RefusedWithoutADenoiser) {
  std::unique_ptr<LiveRender> live = LiveBox(false);
  try {
    live->EditOptions(Json{{"denoise", true}});
    FAIL() << "accepted";
  } catch (const EditError& e) {
    EXPECT_EQ(e.status, 422);
  }
  EXPECT_FALSE(Json::parse(live->DescribeJson())["options"]["denoise_available"].get<bool>());
  EXPECT_FALSE(Json::parse(live->StateJson())["options"].contains("denoise"));
  EXPECT_FALSE(live->Denoising());
  live->Stop();
}

}  // namespace
}  // namespace pt::test
