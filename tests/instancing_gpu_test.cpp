// The CUDA backend renders an instanced scene (rotation, non-uniform scale, mirroring, emissive
// instances) as the CPU backend does: K seeds per backend, Welch's t per 8x8 block of
// luminance, in both BVH layouts. Skips where no GPU is present.
#include <gtest/gtest.h>

#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "src/integrator/render_session.h"
#include "src/io/scene_loader.h"
#include "src/scene/instances.h"
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

// TopLevelChanged on the GPU re-uploads the moved instances, top level and light probabilities:
// the next film is the fresh moved scene's, bit for bit (GPU renders are deterministic).
TEST(InstancingGpu, ASessionSeesTheMovedInstancesAfterTopLevelChanged) {
  if (CudaDeviceCount() == 0) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    BvhBuildOptions options;
    options.layout = layout;
    SceneDesc desc = LoadScene(SourcePath("scenes/instanced_shapes.json"));
    desc.render.width = desc.render.height = 48;
    desc.render.spp = 4;
    Scene scene = BuildScene(desc, options);
    auto session = MakeCudaSession(scene, RenderOptions{});
    session->Render();
    glm::dmat4 to = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.8, 0.2));
    UpdateInstanceTransform(scene, 3, to);
    RebuildTopLevel(scene);
    session->TopLevelChanged();
    session->ResetFilm();
    std::vector<float> moved = session->Render().image.rgb;
    desc.instances[3].toWorld = to;
    std::vector<float> fresh = RenderCuda(BuildScene(desc, options), RenderOptions{}).image.rgb;
    ASSERT_EQ(moved.size(), fresh.size());
    EXPECT_EQ(0, std::memcmp(moved.data(), fresh.data(), moved.size() * sizeof(float)))
        << BvhLayoutName(layout);
  }
}

}  // namespace
}  // namespace pt::test
