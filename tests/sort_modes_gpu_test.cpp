// Shading orders on the GPU (skip without one). `material` runs the same shade kernel in
// another order: bit-identical to `off`. `queues` runs kernels compiled per queue, whose
// floating-point contractions may differ: it agrees statistically, with another seed so that
// the two renders are independent.
#include <gtest/gtest.h>

#include <cstring>

#include "src/integrator/shade_order.h"
#include "tests/material_zoo.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderResult Gpu(const Scene& scene, SortMode sort, SortMethod method, Toggle compact) {
  RenderOptions o;
  o.sort = sort;
  o.sortMethod = method;
  o.compact = compact;
  return RenderCuda(scene, o);
}

TEST(SortModesGpu, MaterialOrderIsBitIdenticalAndQueuesAgree) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string dir = TempDir();
  SceneDesc desc = MaterialZooDesc(dir, 6, 96, 64, 6);
  Scene scene = BuildScene(desc);
  RenderResult off = Gpu(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOn);
  for (SortMethod method : {SortMethod::kCounting, SortMethod::kRadix, SortMethod::kRadixFullWidth})
    for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
      RenderResult r = Gpu(scene, SortMode::kMaterial, method, compact);
      EXPECT_EQ(0, std::memcmp(off.image.rgb.data(), r.image.rgb.data(),
                               off.image.rgb.size() * sizeof(float)))
          << SortMethodName(method) << " compact " << int(compact);
    }
  desc.render.seed = 1234;
  Scene other = BuildScene(desc);
  const std::vector<Window> windows = {
      {0, 0, 48, 48}, {48, 0, 96, 48}, {0, 48, 48, 96}, {48, 48, 96, 96}, {32, 32, 64, 64}};
  for (SortMethod method : {SortMethod::kCounting, SortMethod::kRadix})
    for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
      RenderResult q = Gpu(other, SortMode::kQueues, method, compact);
      EXPECT_EQ(q.stats.sortMode, "queues");
      ExpectWindowsAgree(off.image, q.image, windows, "queues vs off");
      for (uint32_t i = 0; i < kShadeQueueCount; ++i)
        EXPECT_GT(q.stats.stages.shadeQueues[i], 0.0) << ShadeQueueName(i);
    }
}

// More materials than the counting sort's shared-memory table: the radix sort runs instead.
TEST(SortModesGpu, ManyMaterialsFallBackToTheRadixSort) {
  if (!HaveGpu()) GTEST_SKIP() << "no CUDA GPU here";
  std::string dir = TempDir();
  SceneDesc desc = MaterialZooDesc(dir, 4, 32, 4, 3);
  Material extra = desc.materials[0];
  while (desc.materials.size() < kCountingSortMaxKeys) {
    desc.materials.push_back(extra);
    desc.materialNames.push_back("extra" + std::to_string(desc.materials.size()));
  }
  Scene scene = BuildScene(desc);
  RenderResult off = Gpu(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOn);
  RenderResult r = Gpu(scene, SortMode::kMaterial, SortMethod::kCounting, Toggle::kOn);
  EXPECT_EQ(r.stats.sortMethod, "radix");
  EXPECT_EQ(0, std::memcmp(off.image.rgb.data(), r.image.rgb.data(),
                           off.image.rgb.size() * sizeof(float)));
}

}  // namespace
}  // namespace pt::test
