// Same scene and seed give a bit-identical image on the CPU backend whatever the thread
// count, compaction or sort setting, and whatever the number of paths in flight; with either
// sampler (--sampler: independent or sobol numbers are both pure functions of the path).
#include <gtest/gtest.h>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderResult RenderGlassMirror(int threads, Toggle compact, SortMode sort, size_t pathsInFlight,
                               SamplerKind sampler) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_glass_mirror.json"));
  desc.render.width = desc.render.height = 48;
  desc.render.spp = 6;
  RenderOptions opt;
  opt.threads = threads;
  opt.compact = compact;
  opt.sort = sort;
  opt.maxPathsInFlight = pathsInFlight;
  opt.sampler = sampler;
  return RenderCpu(BuildScene(std::move(desc)), opt);
}

TEST(Determinism, BitIdenticalAcrossThreadsCompactionSortAndWaveSize) {
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
  RenderResult first[2];
  for (SamplerKind sampler : {SamplerKind::kIndependent, SamplerKind::kSobol}) {
    RenderResult base = RenderGlassMirror(1, Toggle::kOff, SortMode::kOff, 0, sampler);
    for (const auto& v : variants) {
      RenderResult r = RenderGlassMirror(v.threads, v.compact, v.sort, v.paths, sampler);
      EXPECT_TRUE(BitIdentical(base.image.rgb, r.image.rgb))
          << SamplerKindName(sampler) << ": threads " << v.threads << " compact "
          << int(v.compact) << " sort " << int(v.sort) << " paths " << v.paths;
    }
    EXPECT_EQ(base.stats.nonfiniteSamples, 0u);
    first[int(sampler)] = std::move(base);
  }
  // The sampler is in effect: the two give other images.
  EXPECT_FALSE(BitIdentical(first[0].image.rgb, first[1].image.rgb));
}

}  // namespace
}  // namespace pt::test
