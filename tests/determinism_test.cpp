// Same scene and seed give a bit-identical image on the CPU backend whatever the thread
// count, compaction or sort setting, and whatever the number of paths in flight.
#include <gtest/gtest.h>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderResult RenderGlassMirror(int threads, Toggle compact, SortMode sort, size_t pathsInFlight) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_glass_mirror.json"));
  desc.render.width = desc.render.height = 48;
  desc.render.spp = 6;
  RenderOptions opt;
  opt.threads = threads;
  opt.compact = compact;
  opt.sort = sort;
  opt.maxPathsInFlight = pathsInFlight;
  return RenderCpu(BuildScene(std::move(desc)), opt);
}

TEST(Determinism, BitIdenticalAcrossThreadsCompactionSortAndWaveSize) {
  RenderResult base = RenderGlassMirror(1, Toggle::kOff, SortMode::kOff, 0);
  const struct {
    int threads;
    Toggle compact;
    SortMode sort;
    size_t paths;
  } variants[] = {
      {2, Toggle::kOff, SortMode::kOff, 0},      {1, Toggle::kOn, SortMode::kOff, 0},
      {2, Toggle::kOn, SortMode::kMaterial, 0},  {2, Toggle::kOff, SortMode::kMaterial, 0},
      {2, Toggle::kOn, SortMode::kOff, 1000},    // waves split pixels into tiles
      {2, Toggle::kOn, SortMode::kOff, 48 * 48 * 4},  // several samples per wave
  };
  for (const auto& v : variants) {
    RenderResult r = RenderGlassMirror(v.threads, v.compact, v.sort, v.paths);
    EXPECT_TRUE(BitIdentical(base.image.rgb, r.image.rgb))
        << "threads " << v.threads << " compact " << int(v.compact) << " sort " << int(v.sort)
        << " paths " << v.paths;
  }
  EXPECT_EQ(base.stats.nonfiniteSamples, 0u);
}

}  // namespace
}  // namespace pt::test
