// Shading orders (--sort off|material|queues, --sort-method): images depend only on slots,
// never on the order in which paths are shaded, so every mode and method gives a
// bit-identical CPU image; the shade queues partition the paths exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "cpu_backend/cpu_backend.h"
#include "src/integrator/flag_policy.h"
#include "src/integrator/shade_order.h"
#include "src/integrator/stages/ray_order.h"
#include "tests/material_zoo.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

RenderResult RenderWith(const Scene& scene, SortMode sort, SortMethod method, Toggle compact) {
  RenderOptions o;
  o.threads = 2;
  o.sort = sort;
  o.sortMethod = method;
  o.compact = compact;
  return RenderCpu(scene, o);
}

TEST(ShadeKeys, MaterialsAreRankedByQueueAndEveryZooQueueIsUsed) {
  std::string dir = TempDir();
  Scene scene = BuildScene(MaterialZooDesc(dir, 6, 8, 1, 2));
  ShadeKeys k = MakeShadeKeys(scene);
  uint32_t count = uint32_t(scene.desc.materials.size());
  EXPECT_EQ(k.escapedKey, count);
  EXPECT_EQ(k.keyCount, count + 2);
  EXPECT_GE(1u << k.keyBits, k.keyCount);
  EXPECT_LT(1u << (k.keyBits - 1), k.keyCount);
  // Keys are a permutation of the materials, each inside its queue's run.
  std::vector<uint32_t> sorted = k.materialKey;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t m = 0; m < count; ++m) {
    EXPECT_EQ(sorted[m], m);
    uint32_t q = ShadeQueueOf(scene.desc.materials[m]);
    EXPECT_GE(k.materialKey[m], k.firstKey[q]);
    EXPECT_LT(k.materialKey[m], k.firstKey[q + 1]);
  }
  // The zoo holds every queue (the floor material of the JSON loader aside).
  for (uint32_t q = 0; q < kShadeQueueCount; ++q) EXPECT_TRUE(k.Uses(q)) << ShadeQueueName(q);
  // Every queue used: one ordered kernel rather than a launch per queue.
  EXPECT_EQ(ChooseSortMode(SortMode::kAuto, k, FeatureClass::kGeneral).mode, SortMode::kMaterial);
  EXPECT_EQ(ChooseSortMode(SortMode::kAuto, k, FeatureClass::kSmooth).mode, SortMode::kOff);
  EXPECT_EQ(ChooseSortMode(SortMode::kAuto, k, FeatureClass::kGeneral, false).mode,
            SortMode::kOff);
  EXPECT_EQ(ChooseSortMode(SortMode::kQueues, k, FeatureClass::kGeneral, false).mode,
            SortMode::kQueues);
  EXPECT_EQ(ChooseSortMode(SortMode::kMaterial, k, FeatureClass::kGeneral).mode,
            SortMode::kMaterial);
}

// auto by the surface queues a scene uses: one costly queue gets its own kernel (queues), one
// cheap one stays off; 2-3 queues with a costly one: queues; more: one ordered kernel.
TEST(SortModes, AutoByTheSurfaceQueuesUsed) {
  for (uint32_t q = 0; q < kEscapedQueue; ++q) {
    ShadeKeys k;
    k.queuesUsed = (1u << q) | (1u << kEscapedQueue);
    SortChoice c = ChooseSortMode(SortMode::kAuto, k, FeatureClass::kGeneral);
    EXPECT_EQ(c.mode, CostlyQueue(q) ? SortMode::kQueues : SortMode::kOff) << ShadeQueueName(q);
    EXPECT_EQ(ChooseSortMode(SortMode::kAuto, k, FeatureClass::kGeneral, false).mode, SortMode::kOff);
  }
  // A costly queue among 2 or 3: a kernel per queue; among 4 or more: one ordered kernel.
  uint32_t costly = 0;
  while (!CostlyQueue(costly)) ++costly;
  ShadeKeys k;
  k.queuesUsed = (1u << kEscapedQueue) | (1u << costly);
  uint32_t used = 1;
  for (uint32_t q = 0; q < kEscapedQueue; ++q) {
    if (q == costly) continue;
    k.queuesUsed |= 1u << q;
    ++used;
    SortMode expected = used <= 3 ? SortMode::kQueues : SortMode::kMaterial;
    EXPECT_EQ(ChooseSortMode(SortMode::kAuto, k, FeatureClass::kGeneral).mode, expected) << used;
  }
}

TEST(SortModes, EveryModeAndMethodGivesTheSameImageOnTheZoo) {
  std::string dir = TempDir();
  Scene scene = BuildScene(MaterialZooDesc(dir, 6, 24, 2, 6));
  RenderResult base = RenderWith(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOff);
  EXPECT_EQ(base.stats.sortMode, "off");
  EXPECT_EQ(base.stats.pathsOrdered, 0u);
  for (SortMode mode : {SortMode::kMaterial, SortMode::kQueues, SortMode::kAuto})
    for (SortMethod method : {SortMethod::kCounting, SortMethod::kRadix,
                              SortMethod::kRadixFullWidth})
      for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
        RenderResult r = RenderWith(scene, mode, method, compact);
        EXPECT_TRUE(SameImage(base.image, r.image))
            << SortModeName(mode) << " " << SortMethodName(method) << " compact "
            << int(compact);
        if (mode == SortMode::kAuto) {  // the CPU has no lockstep lanes: auto is off
          EXPECT_EQ(r.stats.sortMode, "off");
          continue;
        }
        EXPECT_GT(r.stats.pathsOrdered, 0u);
        EXPECT_EQ(r.stats.sortMethod, SortMethodName(method));
      }
  // Each queue's kernel ran, and only those: the zoo uses all of them.
  RenderResult q = RenderWith(scene, SortMode::kQueues, SortMethod::kAuto, Toggle::kOn);
  EXPECT_EQ(q.stats.sortMode, "queues");
  for (uint32_t i = 0; i < kShadeQueueCount; ++i)
    EXPECT_GT(q.stats.stages.shadeQueues[i], 0.0) << ShadeQueueName(i);
}

// One path in all (a single pixel, one sample); every path on one material (a wall filling
// the view, no bounce); materials no path reaches (tiles behind the camera).
TEST(SortModes, QueuesWithOneAllAndNoPathsOfAMaterial) {
  std::string dir = TempDir();
  SceneDesc one = MaterialZooDesc(dir, 4, 1, 1, 3);
  SceneDesc all = MaterialZooDesc(dir, 4, 16, 2, 0);
  all.camera.position = vec3(-1.5f, -1.5f, 0.2f);  // tile 0 (diffuse) fills the view
  all.camera.lookAt = vec3(-1.5f, -1.5f, 0.0f);
  SceneDesc none = MaterialZooDesc(dir, 4, 16, 2, 3);
  none.camera.lookAt = none.camera.position + (none.camera.position - vec3(0.0f));
  for (SceneDesc* desc : {&one, &all, &none}) {
    Scene scene = BuildScene(*desc);
    RenderResult base = RenderWith(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOn);
    for (SortMethod method : {SortMethod::kCounting, SortMethod::kRadix})
      for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
        RenderResult r = RenderWith(scene, SortMode::kQueues, method, compact);
        EXPECT_TRUE(SameImage(base.image, r.image))
            << (desc == &one ? "one" : desc == &all ? "all" : "none") << " "
            << SortMethodName(method) << " compact " << int(compact);
      }
  }
}

// More materials than the counting sort's key table holds: the radix sort takes over, over
// the key bits the scene needs, and the image does not change.
TEST(SortModes, MaterialCountAboveTheKeyWidth) {
  std::string materials, objects;
  const int kMaterials = int(kCountingSortMaxKeys) + 10;
  for (int m = 0; m < kMaterials; ++m) {
    float g = 0.2f + 0.6f * float(m) / float(kMaterials);
    materials += (m ? ", " : "") + std::string("\"m") + std::to_string(m) +
                 R"(": {"type": "diffuse", "albedo": [)" + std::to_string(g) + ", 0.5, " +
                 std::to_string(1.0f - g) + "]}";
    float x = float(m % 64) - 32.0f, y = float(m / 64) - 32.0f;
    objects += (m ? ", " : "") + std::string(R"({"type": "quad", "origin": [)") +
               std::to_string(x) + ", " + std::to_string(y) +
               R"(, 0], "u": [1, 0, 0], "v": [0, 1, 0], "material": "m)" + std::to_string(m) +
               "\"}";
  }
  std::string text = R"({"render": {"width": 32, "height": 32, "spp": 2, "max_depth": 3},
      "camera": {"position": [0, 0, 60], "look_at": [0, 0, 0], "fov_y": 60},
      "materials": {)" + materials + R"(}, "objects": [)" + objects + R"(],
      "lights": [{"type": "point", "position": [0, 0, 30], "intensity": [900, 900, 900]}]})";
  Scene scene = BuildScene(LoadSceneFromString(text, "many.json", "."));
  ShadeKeys k = MakeShadeKeys(scene);
  EXPECT_GT(k.keyCount, kCountingSortMaxKeys);
  EXPECT_EQ(ResolveSortMethod(SortMethod::kCounting, k.keyCount), SortMethod::kRadix);
  EXPECT_EQ(k.keyBits, 13u);
  RenderResult base = RenderWith(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOn);
  for (SortMode mode : {SortMode::kMaterial, SortMode::kQueues}) {
    RenderResult r = RenderWith(scene, mode, SortMethod::kCounting, Toggle::kOn);
    EXPECT_EQ(r.stats.sortMethod, "radix");
    EXPECT_TRUE(SameImage(base.image, r.image)) << SortModeName(mode);
  }
}

// The orderings themselves: every method gives keys in order and the same multiset of pairs.
// --ray-order traces each bounce's rays in a sorted copy of the queue: positions move, path
// numbers do not, so the image (and the traversal work) is the same with every shading order,
// with and without compaction (without it finished paths are queued too, and skipped).
TEST(RayOrder, GivesTheSameImageWithEveryShadingOrder) {
  std::string dir = TempDir();
  Scene scene = BuildScene(MaterialZooDesc(dir, 6, 24, 2, 6));
  RenderResult base = RenderWith(scene, SortMode::kOff, SortMethod::kAuto, Toggle::kOn);
  EXPECT_FALSE(base.stats.rayOrderUsed);  // auto: off on the CPU
  for (SortMode mode : {SortMode::kOff, SortMode::kMaterial, SortMode::kQueues})
    for (Toggle compact : {Toggle::kOn, Toggle::kOff}) {
      RenderOptions o;
      o.threads = 2;
      o.sort = mode;
      o.compact = compact;
      o.rayOrder = Toggle::kOn;
      RenderResult r = RenderCpu(scene, o);
      EXPECT_TRUE(r.stats.rayOrderUsed);
      EXPECT_TRUE(SameImage(base.image, r.image))
          << SortModeName(mode) << " compact " << int(compact);
      EXPECT_EQ(r.stats.nodesVisited, base.stats.nodesVisited) << SortModeName(mode);
    }
}

// --prim-pool exists where warps do (the GPU) and for the wide layout of a flat scene; auto
// turns it on from ray ordering's threshold up. The CPU renders with it asked for say it ran
// without (the host walk is per ray; the GPU's image check is in backend_agreement_gpu_test).
TEST(PrimPool, OnlyForWideFlatScenesOnLockstepBackends) {
  const size_t big = size_t(1) << 17, small = big - 1;
  EXPECT_TRUE(ChoosePrimPool(Toggle::kAuto, true, true, big));
  EXPECT_FALSE(ChoosePrimPool(Toggle::kAuto, true, true, small));
  EXPECT_TRUE(ChoosePrimPool(Toggle::kOn, true, true, small));
  EXPECT_FALSE(ChoosePrimPool(Toggle::kOff, true, true, big));
  EXPECT_FALSE(ChoosePrimPool(Toggle::kOn, false, true, big));  // no warps
  EXPECT_FALSE(ChoosePrimPool(Toggle::kOn, true, false, big));  // binary layout or instances
  Scene scene = BuildScene(MaterialZooDesc(TempDir(), 6, 24, 2, 6));
  RenderOptions o;
  o.threads = 2;
  o.primPool = Toggle::kOn;
  EXPECT_FALSE(RenderCpu(scene, o).stats.primPoolUsed);
}

// The key: the direction's octant in the top 3 of 24 bits, then the origin's Morton code in
// the scene's bounding cube (clamped outside it, and for NaN).
TEST(RayOrder, KeyIsOctantThenMortonCode) {
  SceneView s;
  s.sceneCenter = vec3(0.0f);
  s.sceneRadius = 1.0f;
  const vec3 o(0.0f);
  for (uint32_t oct = 0; oct < 8; ++oct) {
    vec3 d((oct & 1) ? -1.0f : 1.0f, (oct & 2) ? -1.0f : 1.0f, (oct & 4) ? -1.0f : 1.0f);
    EXPECT_EQ(RayOrderKey(s, o, d) >> 21, oct);
  }
  const vec3 up(0.0f, 0.0f, 1.0f);
  EXPECT_EQ(RayOrderKey(s, vec3(-1.0f), up), 0u);
  EXPECT_EQ(RayOrderKey(s, vec3(5.0f), up), (1u << 21) - 1u);  // outside: the last cell
  EXPECT_EQ(RayOrderKey(s, vec3(std::nanf("")), up), 0u);
  // x is the lowest Morton bit: one cell along +x moves the key by 1, along +y by 2, +z by 4.
  const float cell = 2.0f / 128.0f;
  const vec3 p(-1.0f + 0.5f * cell);
  EXPECT_EQ(RayOrderKey(s, p + vec3(cell, 0, 0), up) - RayOrderKey(s, p, up), 1u);
  EXPECT_EQ(RayOrderKey(s, p + vec3(0, cell, 0), up) - RayOrderKey(s, p, up), 2u);
  EXPECT_EQ(RayOrderKey(s, p + vec3(0, 0, cell), up) - RayOrderKey(s, p, up), 4u);
  EXPECT_LT(RayOrderKey(s, vec3(1.0f), -up), 1u << kRayOrderKeyBits);
}

TEST(OrderByKey, EveryMethodOrdersThePairs) {
  CpuBackend backend(1);
  const uint32_t n = 1000, keyCount = 37;
  std::vector<uint32_t> keys(n), values(n), keysOut(n), valuesOut(n);
  for (uint32_t i = 0; i < n; ++i) {
    keys[i] = (i * 7919u) % keyCount;
    values[i] = i;
  }
  keys[5] = keyCount - 1;  // and key 3 appears nowhere, key 36 ...
  for (uint32_t& k : keys)
    if (k == 3) k = 4;
  for (SortMethod method : {SortMethod::kCounting, SortMethod::kRadix,
                            SortMethod::kRadixFullWidth}) {
    OrderShape shape{method, 6, keyCount, n};
    backend.ReserveOrdering(shape);
    backend.OrderByKey(Stage::kSort, shape,
                       OrderArrays{keys.data(), values.data(), keysOut.data(), valuesOut.data()});
    EXPECT_TRUE(std::is_sorted(keysOut.begin(), keysOut.end())) << SortMethodName(method);
    std::vector<bool> seen(n, false);
    for (uint32_t i = 0; i < n; ++i) {
      ASSERT_LT(valuesOut[i], n);
      EXPECT_FALSE(seen[valuesOut[i]]);
      seen[valuesOut[i]] = true;
      EXPECT_EQ(keys[valuesOut[i]], keysOut[i]);
    }
    EXPECT_EQ(QueueStart(keysOut.data(), n, 3), QueueStart(keysOut.data(), n, 4));
    EXPECT_EQ(QueueStart(keysOut.data(), n, keyCount), n);
    EXPECT_EQ(QueueStart(keysOut.data(), n, 0), 0u);
  }
}

}  // namespace
}  // namespace pt::test
