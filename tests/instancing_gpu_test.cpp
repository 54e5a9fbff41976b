// The CUDA backend renders an instanced scene (rotation, non-uniform scale, mirroring, emissive
// instances) as the CPU backend does: K seeds per backend, Welch's t per 8x8 block of
// luminance, in both BVH layouts. Skips where no GPU is present.
#include <gtest/gtest.h>

#include "src/io/scene_loader.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {


TEST(InstancingGpu, InstancedSceneAgreesWithTheCpu) {
  if (CudaDeviceCount() == 0) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  const int kSeeds = 8;
  const double kBlockAlpha = 0.01;
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    BvhBuildOptions options;
    options.layout = layout;
    std::vector<std::vector<double>> cpu, gpu;
    for (int k = 0; k < kSeeds; ++k) {
      SceneDesc desc = LoadScene(SourcePath("scenes/instanced_shapes.json"));
      desc.render.width = desc.render.height = 64;
      desc.render.spp = 16;
      desc.render.seed = 1000 + k;
      cpu.push_back(BlockLuminance(RenderOnCpu(BuildScene(desc, options)).image));
      desc.render.seed = 2000 + k;
      RenderResult r = RenderCuda(BuildScene(desc, options), RenderOptions{});
      EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
      gpu.push_back(BlockLuminance(r.image));
    }
    int blocks = int(cpu[0].size()), failing = FailingBlocks(cpu, gpu, kBlockAlpha);
    EXPECT_LE(failing, BinomialUpperBound(blocks, kBlockAlpha, 1e-3))
        << BvhLayoutName(layout) << ": " << failing << " of " << blocks << " blocks differ";
  }
}

}  // namespace
}  // namespace pt::test
