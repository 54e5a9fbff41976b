// --warm-up: a short wave traced and discarded before the render so that a backend that loads
// kernels at their first launch (CUDA's lazy loading) does so outside the render's time. The
// CPU has nothing to load (auto: off) but runs the same warm-up when asked, so these tests
// check on it that nothing of the discarded wave reaches the image or the statistics.
#include <gtest/gtest.h>

#include "src/integrator/render_session.h"
#include "src/integrator/shade_order.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderOptions WarmUp(Toggle warmUp) {
  RenderOptions o;
  o.threads = 2;
  o.warmUp = warmUp;
  return o;
}

void ExpectSameRender(const RenderResult& off, const RenderResult& on, const char* what) {
  EXPECT_TRUE(SameImage(off.image, on.image)) << what;
  EXPECT_EQ(off.image.samples, on.image.samples) << what;
  EXPECT_EQ(off.stats.samples, on.stats.samples) << what;
  EXPECT_EQ(off.stats.cameraRays, on.stats.cameraRays) << what;
  EXPECT_EQ(off.stats.extensionRays, on.stats.extensionRays) << what;
  EXPECT_EQ(off.stats.shadowRays, on.stats.shadowRays) << what;
  EXPECT_EQ(off.stats.nodesVisited, on.stats.nodesVisited) << what;
  EXPECT_EQ(off.stats.nonfiniteSamples, on.stats.nonfiniteSamples) << what;
  EXPECT_FALSE(off.stats.warmedUp) << what;
  EXPECT_TRUE(on.stats.warmedUp) << what;
  EXPECT_EQ(off.stats.warmUpMs, 0.0) << what;
  EXPECT_GT(on.stats.warmUpMs, 0.0) << what;
}

TEST(WarmUp, AutoIsOffOnTheCpu) {
  Scene scene = SmallScene(SourcePath("scenes/cornell_box.json"), 16, 12, 2);
  RenderResult r = RenderCpu(scene, WarmUp(Toggle::kAuto));
  EXPECT_FALSE(r.stats.warmedUp);
  EXPECT_EQ(r.stats.warmUpMs, 0.0);
}

// Glass and mirrors (several bounces, every shade queue), with and without compaction and
// material sorting: the image, the ray counts and the traversal work are those without it.
TEST(WarmUp, LeavesNothingInTheImageOrTheStatistics) {
  Scene scene = SmallScene(SourcePath("scenes/cornell_glass_mirror.json"), 96, 64, 3);
  for (auto [compact, sort] : {std::pair{Toggle::kOn, SortMode::kOff},
                               std::pair{Toggle::kOff, SortMode::kMaterial}}) {
    RenderOptions off = WarmUp(Toggle::kOff), on = WarmUp(Toggle::kOn);
    off.compact = on.compact = compact;
    off.sort = on.sort = sort;
    ExpectSameRender(RenderCpu(scene, off), RenderCpu(scene, on), SortModeName(sort));
  }
}

// A crop window smaller than the warm-up wave, adaptive sampling (its active pixel list is
// reset with the film), and a participating medium.
TEST(WarmUp, SmallCropsAdaptiveRendersAndMedia) {
  Scene box = SmallScene(SourcePath("scenes/cornell_box.json"), 64, 48, 4);
  RenderOptions off = WarmUp(Toggle::kOff), on = WarmUp(Toggle::kOn);
  off.crop = on.crop = CropWindow{30, 20, 37, 25};
  ExpectSameRender(RenderCpu(box, off), RenderCpu(box, on), "crop");
  off = WarmUp(Toggle::kOff), on = WarmUp(Toggle::kOn);
  off.adaptive = on.adaptive = Toggle::kOn;
  ExpectSameRender(RenderCpu(box, off), RenderCpu(box, on), "adaptive");
  Scene fog = SmallScene(SourcePath("scenes/cornell_fog.json"), 48, 32, 2);
  ExpectSameRender(RenderCpu(fog, WarmUp(Toggle::kOff)), RenderCpu(fog, WarmUp(Toggle::kOn)),
                   "medium");
}

// A session warmed up at its allocation, then given a saved film to continue (a resume):
// the film it ends with is the uninterrupted render's.
TEST(WarmUp, ASessionResumedFromAFilmEndsAsTheOneShotRender) {
  Scene scene = SmallScene(SourcePath("scenes/cornell_glass_mirror.json"), 40, 32, 6);
  RenderResult whole = RenderCpu(scene, WarmUp(Toggle::kOff));
  auto first = MakeCpuSession(scene, WarmUp(Toggle::kOn));
  first->RenderRange(0, 2);
  FilmState saved = first->SaveFilm();
  auto second = MakeCpuSession(scene, WarmUp(Toggle::kOn));
  second->LoadFilm(saved);
  second->RenderUpTo(6);
  EXPECT_TRUE(SameImage(whole.image, second->Image()));
  EXPECT_TRUE(second->Stats().warmedUp);
}

}  // namespace
}  // namespace pt::test
