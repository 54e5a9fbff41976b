// The scripting layer behind the Python module (src/scripting/), without Python: keyword options
// parsed as the command line parses them, and a ScriptScene's edits and renders (also run under
// the sanitizers, where the module itself is not built). tests/python/ tests the module.
#include <gtest/gtest.h>

#include "src/app/run.h"
#include "src/io/scene_loader.h"
#include "src/scripting/script_render.h"
#include "tests/cli_parse_util.h"
#include "tests/test_util.h"

namespace pt {
namespace {

AppBackends ScriptCpuBackends() {
  AppBackends b;
  b.cpuSession = &MakeCpuSession;
  return b;
}

ScriptRequest SmallRequest(OptionKeywords keywords = {}) {
  OptionKeywords all = {{"width", "16"}, {"height", "12"}, {"spp", "4"}, {"max_depth", "3"},
                        {"seed", "5"}, {"backend", "cpu"}, {"threads", "2"}};
  all.insert(all.end(), keywords.begin(), keywords.end());
  ScriptRequest request;
  request.keywords = all;
  request.cli = OptionsFromKeywords(all);
  return request;
}

bool SameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(ScriptOptions, KeywordsAreParsedAsTheCommandLine) {
  CliOptions k = OptionsFromKeywords({{"max_depth", "3"}, {"sort", "queues"}, {"crop", "1,2,9,8"},
                                      {"compact", "off"}, {"env_strength", "0.5"}});
  CliOptions c = test::Parse({"s.json", "-o", "x.png", "--max-depth", "3", "--sort", "queues",
                              "--crop", "1", "2", "9", "8", "--compact", "off",
                              "--env-strength", "0.5"});
  EXPECT_EQ(k.maxDepth, c.maxDepth);
  EXPECT_EQ(k.sort, c.sort);
  EXPECT_EQ(k.crop->x1, c.crop->x1);
  EXPECT_EQ(k.compact, c.compact);
  EXPECT_EQ(k.envStrength, c.envStrength);
  EXPECT_THROW(OptionsFromKeywords({{"max_dpeth", "3"}}), UnknownOptionError);
  EXPECT_THROW(OptionsFromKeywords({{"hdr", "x.exr"}}), UnknownOptionError);
  EXPECT_THROW(OptionsFromKeywords({{"max-depth", "3"}}), UnknownOptionError);
  EXPECT_THROW(OptionsFromKeywords({{"quiet", "on"}}), UnknownOptionError);
  try {
    OptionsFromKeywords({{"sort", "sideways"}});
    FAIL();
  } catch (const CliError& e) {
    EXPECT_EQ(test::ParseError({"s.json", "-o", "x.png", "--sort", "sideways"}), e.what());
  }
}

TEST(ScriptScene, InstanceAndMaterialEditsEqualAFreshLoad) {
  std::string path = test::SourcePath("scenes/instanced_shapes.json");
  auto scene = ScriptScene::Load(path, "");
  AppBackends backends = ScriptCpuBackends();
  ScriptResult before = RenderScript(*scene, SmallRequest(), backends);
  Json moved = {{"translate", {0.1, 0.2, 0.3}}, {"rotate", {0, 45, 0}}};
  scene->SetInstanceTransform(1, moved);
  scene->EditMaterial("red", Json{{"albedo", {0.2, 0.3, 0.4}}});
  EXPECT_THROW(scene->EditMaterial("red", Json{{"albedo", {2, 0, 0}}}), SceneError);
  EXPECT_THROW(scene->SetInstanceTransform(9, moved), SceneError);
  ScriptResult edited = RenderScript(*scene, SmallRequest(), backends);
  EXPECT_EQ(edited.stats["time_ms"]["bvh_build"].get<double>(), 0.0);  // top level only
  // The same edits in the file's text, loaded afresh.
  auto fresh = ScriptScene::FromText(scene->Text(), path,
                                     test::SourcePath("scenes"), "");
  ScriptResult expected = RenderScript(*fresh, SmallRequest(), backends);
  EXPECT_TRUE(SameBits(edited.image.rgb, expected.image.rgb));
  EXPECT_FALSE(SameBits(edited.image.rgb, before.image.rgb));
}

TEST(ScriptScene, ProgressiveEndsAtTheWholeRender) {
  auto scene = ScriptScene::Load(test::SourcePath("scenes/cornell_box.json"), "");
  AppBackends backends = ScriptCpuBackends();
  ScriptResult whole = RenderScript(*scene, SmallRequest(), backends);
  ProgressiveScript steps(*scene, SmallRequest(), backends, {});
  ScriptResult step;
  std::vector<uint32_t> spp;
  while (steps.Next(&step)) spp.push_back(steps.Spp());
  EXPECT_EQ(spp, (std::vector<uint32_t>{1, 2, 4}));
  EXPECT_TRUE(SameBits(step.image.rgb, whole.image.rgb));
  EXPECT_EQ(step.stats["stop_reason"], "completed");
  // A stop callback ends a render between waves.
  ScriptRequest stopped = SmallRequest({{"max_paths", "64"}});
  int polls = 0;
  stopped.shouldStop = [&polls] { return ++polls > 2; };
  ScriptResult partial = RenderScript(*scene, stopped, backends);
  EXPECT_TRUE(partial.stopped);
  EXPECT_LT(partial.stats["samples"].get<uint64_t>(), 16u * 12u * 4u);
}

}  // namespace
}  // namespace pt
