// The three integrators estimate the same integral: on the Cornell box their means agree.
#include <gtest/gtest.h>

#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderResult RenderCornell(IntegratorMode mode, int spp) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_box.json"));
  desc.render.width = desc.render.height = 64;
  desc.render.spp = spp;
  desc.render.seed = 11 + int(mode);  // independent estimates
  RenderOptions opt;
  opt.integrator = mode;
  return RenderOnCpu(BuildScene(std::move(desc)), opt);
}

TEST(IntegratorAgreement, MisBsdfNeeAgreeInTheMeanOnCornellBox) {
  RenderResult mis = RenderCornell(IntegratorMode::kMis, 128);
  RenderResult nee = RenderCornell(IntegratorMode::kNee, 128);
  RenderResult bsdf = RenderCornell(IntegratorMode::kBsdf, 512);
  const std::pair<const RenderResult*, const RenderResult*> pairs[] = {
      {&mis, &nee}, {&mis, &bsdf}, {&nee, &bsdf}};
  // Image quadrants and the whole image, 3 channels, 3 pairs: 45 comparisons. Each uses
  // z = 4.42 (two-sided p = 1e-5) on the difference of means over the variance from the
  // films' per-pixel sample variances, so the family's false-alarm probability is < 4.5e-4.
  // Means over 1024+ pixels of hundreds of samples are close to normal.
  const int windows[5][4] = {{0, 0, 32, 32}, {32, 0, 64, 32}, {0, 32, 32, 64},
                             {32, 32, 64, 64}, {0, 0, 64, 64}};
  for (auto [a, b] : pairs)
    for (auto& w : windows)
      for (int c = 0; c < 3; ++c) {
        WindowMean ma = MeanOverWindow(a->image, c, w[0], w[1], w[2], w[3]);
        WindowMean mb = MeanOverWindow(b->image, c, w[0], w[1], w[2], w[3]);
        double sigma = std::sqrt(ma.varianceOfMean + mb.varianceOfMean);
        EXPECT_LT(std::abs(ma.mean - mb.mean), kZ1e5 * sigma)
            << "window " << w[0] << "," << w[1] << " channel " << c << ": " << ma.mean
            << " vs " << mb.mean;
      }
  // MIS should not be noisier than BSDF sampling alone at equal spp on this scene.
  EXPECT_LT(MeanOverImage(mis.image, 1).varianceOfMean * 128,
            MeanOverImage(bsdf.image, 1).varianceOfMean * 512);
}

}  // namespace
}  // namespace pt::test
