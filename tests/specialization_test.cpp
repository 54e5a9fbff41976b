// Stage variants specialised to a scene's effects give the general variant's image, bit for
// bit on the CPU (same functions, same random numbers for the same dimensions).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "src/scene/effects.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

TEST(Specialization, EveryProjectSceneIsBitIdenticalToTheGeneralVariant) {
  int scenes = 0, flat = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SourcePath("scenes"))) {
    if (entry.path().extension() != ".json") continue;
    SceneDesc desc = LoadScene(entry.path().string());
    desc.render.width = desc.render.height = 24;
    desc.render.spp = 4;
    Scene scene = BuildScene(std::move(desc));
    RenderOptions specialised, general;
    general.specialize = false;
    RenderResult a = RenderOnCpu(scene, specialised), b = RenderOnCpu(scene, general);
    EXPECT_EQ(b.stats.specialization, "general");
    EXPECT_EQ(0, std::memcmp(a.image.rgb.data(), b.image.rgb.data(),
                             a.image.rgb.size() * sizeof(float)))
        << entry.path().filename() << " (variant " << a.stats.specialization << ")";
    EXPECT_EQ(a.stats.nonfiniteSamples, 0u) << entry.path().filename();
    flat += a.stats.specialization.find("-flat") != std::string::npos;
    ++scenes;
  }
  EXPECT_GE(scenes, 3);
  EXPECT_GE(flat, 2);  // the Cornell boxes run the flat copy (no vertex normals, no light tree)
}

// The statistics name the copy that ran: the queue kernels (--sort queues) have no flat copy.
TEST(Specialization, TheStatisticsNameTheFlatCopyOnlyWhereItRuns) {
  SceneDesc desc = LoadScene(SourcePath("scenes/cornell_box.json"));
  desc.render.width = desc.render.height = 16;
  desc.render.spp = 2;
  Scene scene = BuildScene(std::move(desc));
  RenderOptions inOrder, material, queues;
  inOrder.sort = SortMode::kOff;
  material.sort = SortMode::kMaterial;
  queues.sort = SortMode::kQueues;
  EXPECT_EQ(RenderOnCpu(scene, inOrder).stats.specialization, "diffuse-flat");
  EXPECT_EQ(RenderOnCpu(scene, material).stats.specialization, "diffuse-flat");
  RenderResult q = RenderOnCpu(scene, queues);
  EXPECT_EQ(q.stats.sortMode, "queues");
  EXPECT_EQ(q.stats.specialization, "diffuse");
}

TEST(Specialization, EffectsAndVariantsFollowTheScene) {
  auto effectsOf = [](const char* materials) {
    std::string json = std::string(R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 2},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
      "materials": )") + materials + R"(,
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"},
                  {"type": "quad", "origin": [-1, 2, -1], "u": [2, 0, 0], "v": [0, 0, 2],
                   "material": "lamp"}]})";
    return AnalyzeEffects(SceneFromJson(json));
  };
  const char* lamp = R"("lamp": {"type": "emissive", "radiance": [1, 1, 1]})";
  uint32_t diffuse = effectsOf((std::string("{\"m\": {\"type\": \"diffuse\", \"albedo\": [0.5, 0.5, 0.5]}, ") + lamp + "}").c_str());
  EXPECT_EQ(diffuse, kEffectDiffuse | kEffectEmissive | kEffectAreaLights);
  EXPECT_EQ(ChooseFeatureClass(diffuse), FeatureClass::kDiffuse);
  uint32_t glass = effectsOf((std::string("{\"m\": {\"type\": \"dielectric\", \"ior\": 1.5, \"absorption\": [0.1, 0, 0]}, ") + lamp + "}").c_str());
  EXPECT_TRUE(glass & kEffectAbsorption);
  EXPECT_FALSE(glass & kEffectDiffuse);
  EXPECT_EQ(ChooseFeatureClass(glass), FeatureClass::kSmooth);
  EXPECT_EQ(ChooseFeatureClass(glass | kEffectTextures), FeatureClass::kGeneral);
  EXPECT_EQ(ChooseFeatureClass(kEffectDiffuse | kEffectPlastic), FeatureClass::kGeneral);
  EXPECT_EQ(ChooseFeatureClass(kEffectConductor | kEffectRoughLobes), FeatureClass::kGeneral);
  EXPECT_EQ(EffectNames(diffuse), (std::vector<std::string>{"diffuse", "emissive", "area_lights"}));
}

}  // namespace
}  // namespace pt::test
