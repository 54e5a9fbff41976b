// RenderSession: ranges of samples, saved and loaded films, and resets give exactly the film
// a one-shot render gives (CPU, bit for bit), since every pixel adds its samples in order.
#include <gtest/gtest.h>

#include "src/distributed/film_merge.h"
#include "src/integrator/render_session.h"
#include "src/integrator/wave_plan.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

Scene GlassMirror(int spp) {
  return SmallScene(SourcePath("scenes/cornell_glass_mirror.json"), 40, 32, spp);
}

RenderOptions TwoThreads(size_t pathsInFlight = 0) {
  RenderOptions o;
  o.threads = 2;
  o.maxPathsInFlight = pathsInFlight;
  return o;
}

TEST(RenderSession, RangesAddUpToTheOneShotRender) {
  Scene scene = GlassMirror(7);
  RenderResult whole = RenderCpu(scene, TwoThreads());
  auto session = MakeCpuSession(scene, TwoThreads());
  EXPECT_EQ(session->RenderRange(0, 3), 40u * 32u * 3u);
  EXPECT_EQ(session->RenderRange(3, 7), 40u * 32u * 4u);
  FilmImage split = session->Image();
  EXPECT_TRUE(BitIdentical(whole.image.rgb, split.rgb));
  EXPECT_TRUE(BitIdentical(whole.image.variance, split.variance));
  EXPECT_EQ(split.samples, whole.image.samples);
}

// An interrupted render: a film whose pixels hold different counts (the stop came between
// waves of a tiled plan), saved, loaded into a new session and continued to spp.
TEST(RenderSession, ContinuingAnUnevenFilmEqualsTheUninterruptedRender) {
  Scene scene = GlassMirror(5);
  RenderResult whole = RenderCpu(scene, TwoThreads());
  int waves = 0;
  RenderCallbacks stopAfterFour;
  stopAfterFour.shouldStop = [&] { return waves >= 4; };
  stopAfterFour.onProgress = [&](uint64_t, uint64_t) { ++waves; };
  // 500 paths a wave: tiles of 500, 500 and 280 pixels a sample, so four waves leave the
  // first 500 pixels one sample ahead.
  auto first = MakeCpuSession(scene, TwoThreads(500), stopAfterFour);
  RenderResult partial = first->Render();
  EXPECT_EQ(partial.stats.samples, 1780u);
  FilmState saved = first->SaveFilm();
  uint32_t lo = *std::min_element(saved.count.begin(), saved.count.end());
  uint32_t hi = *std::max_element(saved.count.begin(), saved.count.end());
  EXPECT_LT(lo, hi);  // the case under test

  auto second = MakeCpuSession(scene, TwoThreads());
  second->LoadFilm(saved);
  RenderResult resumed = second->Render();
  EXPECT_EQ(resumed.stats.samples, 40u * 32u * 5u - 1780u);
  EXPECT_DOUBLE_EQ(resumed.stats.sppMean, 5.0);
  EXPECT_TRUE(BitIdentical(whole.image.rgb, resumed.image.rgb));
  EXPECT_TRUE(BitIdentical(whole.image.variance, resumed.image.variance));
}

TEST(RenderSession, ResetStartsOverAndACameraChangeTakesEffect) {
  Scene scene = GlassMirror(2);
  auto session = MakeCpuSession(scene, TwoThreads());
  session->RenderRange(0, 2);
  FilmImage before = session->Image();
  session->ResetFilm();
  session->RenderRange(0, 2);
  EXPECT_TRUE(BitIdentical(before.rgb, session->Image().rgb));

  Camera turned = scene.camera;
  turned.forward = -turned.forward;  // looks out of the box's open side: into the black
  turned.right = -turned.right;
  session->SetCamera(turned);
  session->ResetFilm();
  session->RenderRange(0, 2);
  FilmImage away = session->Image();
  EXPECT_LT(MeanOverImage(away, 1).mean, 0.5 * MeanOverImage(before, 1).mean);
}

// A film saved over another one (a leaf's save over a merged-away film under --chunks and
// MPI) equals a fresh save, keeps the old film's memory where the size matches, and drops
// feature channels the session does not keep.
TEST(RenderSession, SavingOverAnotherFilmEqualsAFreshSave) {
  Scene scene = GlassMirror(2);
  auto session = MakeCpuSession(scene, TwoThreads());
  session->RenderRange(0, 2);
  FilmState fresh = session->SaveFilm();
  RenderOptions withFeatures = TwoThreads();
  withFeatures.featureBuffers = true;
  auto other = MakeCpuSession(scene, withFeatures);
  other->RenderRange(0, 1);
  FilmState reused = other->SaveFilm();
  ASSERT_FALSE(reused.albedoSum.empty());
  ASSERT_FALSE(SameFilm(reused, fresh));
  const glm::dvec3* memory = reused.mean.data();
  session->SaveFilmInto(reused);
  EXPECT_TRUE(SameFilm(reused, fresh));
  EXPECT_EQ(reused.mean.data(), memory);
  FilmState larger = EmptyFilm(80, 64, true);
  session->SaveFilmInto(larger);
  EXPECT_TRUE(SameFilm(larger, fresh));
}

// A snapshot keeps the film as it was while the film is cleared and rendered into again
// (a render lane saves a leaf from it while it renders the next).
TEST(RenderSession, ASnapshotKeepsTheFilmWhileTheNextRangeRenders) {
  Scene scene = GlassMirror(4);
  auto session = MakeCpuSession(scene, TwoThreads());
  FilmState none;
  EXPECT_THROW(session->SaveSnapshotInto(none), std::logic_error);
  session->RenderRange(0, 2);
  FilmState first = session->SaveFilm();
  session->SnapshotFilm();
  session->ResetFilm();
  session->RenderRange(2, 4);
  FilmState saved;
  session->SaveSnapshotInto(saved);
  EXPECT_TRUE(SameFilm(saved, first));
  EXPECT_FALSE(SameFilm(session->SaveFilm(), first));
}

// The image resolved on the backend (ResolveFilmPixel) is the saved film's resolved on the host
// (ResolveFilmImage), float for float: float and double films, with and without the feature
// and half-film channels, after a range that leaves some pixels without samples (a crop of
// an adaptive render is not needed: pixels of count 0 and 1 come from the ranges here).
TEST(RenderSession, TheBackendsResolvedImageIsTheSavedFilmsResolved) {
  Scene scene = GlassMirror(3);
  for (int variant = 0; variant < 4; ++variant) {
    RenderOptions o = TwoThreads();
    o.filmDouble = variant == 1 || variant == 3;
    o.featureBuffers = variant >= 2;
    o.halfFilms = variant == 3;
    auto session = MakeCpuSession(scene, o);
    for (auto [begin, end] : {std::pair{0u, 0u}, std::pair{0u, 1u}, std::pair{1u, 3u}}) {
      session->RenderRange(begin, end);
      const FilmImage backend = session->Image();
      const FilmImage host = ResolveFilmImage(session->SaveFilm());
      EXPECT_TRUE(BitIdentical(backend.rgb, host.rgb)) << variant << " to " << end;
      EXPECT_TRUE(BitIdentical(backend.variance, host.variance)) << variant << " to " << end;
      EXPECT_EQ(backend.samples, host.samples);
      EXPECT_TRUE(BitIdentical(backend.albedo, host.albedo)) << variant;
      EXPECT_TRUE(BitIdentical(backend.normal, host.normal)) << variant;
      EXPECT_TRUE(BitIdentical(backend.depth, host.depth)) << variant;
      EXPECT_TRUE(BitIdentical(backend.evenRgb, host.evenRgb)) << variant;
      EXPECT_EQ(backend.evenSamples, host.evenSamples);
      EXPECT_EQ(backend.albedo.empty(), !o.featureBuffers);
      EXPECT_EQ(backend.evenRgb.empty(), !o.halfFilms);
    }
  }
}

TEST(RenderSession, AFilmOfAnotherSizeIsRefused) {
  Scene scene = GlassMirror(1);
  auto session = MakeCpuSession(scene, TwoThreads());
  FilmState wrong = session->SaveFilm();
  wrong.width += 1;
  EXPECT_THROW(session->LoadFilm(wrong), std::invalid_argument);
}

// The paths a render allocates: the largest wave AppendWaves cuts for the whole crop, over
// single pixels, one sample, waves of one path, of one pixel row, and more paths than samples.
TEST(RenderSession, ThePlansCapacityIsItsLargestWave) {
  for (int w : {1, 7, 64}) {
    for (int h : {1, 5, 64}) {
      for (int spp : {0, 1, 3, 100}) {
        for (size_t maxPaths : {size_t(0), size_t(1), size_t(7), size_t(64), size_t(1000000)}) {
          RenderSettings render;
          render.width = w;
          render.height = h;
          render.spp = spp;
          WavePlan plan = MakeWavePlan(render, CropWindow{}, 4096, maxPaths);
          std::vector<WaveInfo> waves;
          AppendWaves(plan.base, nullptr, plan.cropPixels, 0, plan.spp, plan.maxPaths, waves);
          uint32_t largest = 0;
          for (const WaveInfo& wave : waves) largest = std::max(largest, wave.PathCount());
          EXPECT_EQ(plan.pathCapacity, largest)
              << w << "x" << h << " " << spp << " spp, " << maxPaths;
        }
      }
    }
  }
}

}  // namespace
}  // namespace pt::test
