// Lighting defaults of a model file rendered directly, end to end through the binary: the
// default environment lights it whatever lights the file brings (a directional light here,
// as IridescenceSuzanne has), `--env none` removes it, and a nearly black image says so with
// its likely cause, while a normal render says nothing. BlackImageWarning's own rules on
// synthetic images.
#include <gtest/gtest.h>

#include <filesystem>

#include "src/app/cli.h"
#include "src/scene/scene_checks.h"
#include "tests/cli_parse_util.h"
#include "tests/env_test_util.h"
#include "tests/gltf_scene_writer.h"

namespace pt::test {
namespace {

TEST(LightingDefaults, EnvNoneParses) {
  EXPECT_EQ(Parse({"m.glb", "-o", "o.png", "--env", "none"}).envPath, kEnvNone);
  EXPECT_EQ(Parse({"m.glb", "-o", "o.png", "--env", "./none"}).envPath, "./none");
}

// A grey square facing the front camera (+Z) and a directional light that, with lightFront
// false, shines on its back (travelling towards +Z, the node turned about Y).
std::string WriteLitSquareModel(const std::string& dir, const std::string& name, bool light,
                       bool lightFront) {
  GltfSceneWriter w;
  w.doc["materials"] = {{{"pbrMetallicRoughness",
                          {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}}}}};
  int mesh = w.AddMesh({vec3(-1, -1, 0), vec3(1, -1, 0), vec3(1, 1, 0), vec3(-1, 1, 0)},
                       {0, 1, 2, 0, 2, 3}, 0);
  w.AddNode({{"mesh", mesh}});
  if (light) {
    GltfSceneWriter::Json node = GltfSceneWriter::Json::object();
    if (!lightFront) node["rotation"] = {0, 1, 0, 0};
    w.AddNode(GltfSceneWriter::LightNode(
        w.AddLight({{"type", "directional"}, {"intensity", 2}}), node));
  }
  return w.Write(dir, name, true);
}

class LightingDefaultsRun : public ::testing::Test {
 protected:
  int Run(const std::string& model, const std::string& options, std::string* output) {
    return RunCommand(BinaryPath("pathtracer") + " " + model + " -o " + (dir_ / "out.pfm") +
                          " --width 24 --height 16 --spp 4 --backend cpu --quiet " + options,
                      output);
  }
  std::vector<float> Image() {
    int w, h;
    std::vector<float> rgb;
    ReadPfmRgb(dir_ / "out.pfm", &w, &h, &rgb);
    return rgb;
  }
  ScopedDir dir_;
};

TEST_F(LightingDefaultsRun, TheEnvironmentLightsAFileWithItsOwnLight) {
  std::string behind = WriteLitSquareModel(dir_.path, "behind", true, false);
  std::string out;
  ASSERT_EQ(Run(behind, "", &out), 0) << out;
  std::vector<float> lit = Image();
  EXPECT_EQ(lit[0], 1.0f);  // a corner sees the default environment, radiance 1
  float centre = lit[3 * (8 * 24 + 12)];
  EXPECT_GT(centre, 0.2f);  // the square, lit by the environment (its light is behind it)
  EXPECT_LT(centre, 0.6f);
  EXPECT_NE(out.find("lit by the default environment"), std::string::npos) << out;
  EXPECT_NE(out.find("and by the file's 1 light"), std::string::npos) << out;
  EXPECT_EQ(out.find("nearly black"), std::string::npos) << out;

  // --env none: only the light behind the square lights it; the image is black and says why.
  ASSERT_EQ(Run(behind, "--env none", &out), 0) << out;
  for (float v : Image()) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(out.find("lit by the default environment"), std::string::npos) << out;
  EXPECT_NE(out.find("the image is nearly black: 100.0% of its pixels"), std::string::npos)
      << out;
  EXPECT_NE(out.find("no environment (--env none removed the environment): only the scene's 1 "
                     "light lights it"),
            std::string::npos)
      << out;

  // A light in front of it, no environment: a lit square on black is not "nearly black".
  ASSERT_EQ(Run(WriteLitSquareModel(dir_.path, "front", true, true), "--env none", &out), 0) << out;
  EXPECT_GT(Image()[3 * (8 * 24 + 12)], 0.1f);
  EXPECT_EQ(out.find("nearly black"), std::string::npos) << out;

  // (--serve opens model files with this same default lighting: tests/serve_state_test.cpp
  // and the browser test.)

  // No light at all and no environment.
  ASSERT_EQ(Run(WriteLitSquareModel(dir_.path, "unlit", false, false), "--env none", &out), 0) << out;
  EXPECT_NE(out.find("likely cause: nothing lights the scene (--env none removed the "
                     "environment)"),
            std::string::npos)
      << out;
}

// The rules on synthetic images of a scene lit only by a point light: 95% black pixels or more
// warn, fewer do not; a dim image names the output's range as the cause.
TEST(LightingDefaults, BlackImageWarningThresholdsAndCauses) {
  Scene scene = BuildScene(LoadSceneFromString(R"({
      "render": {"width": 10, "height": 10, "spp": 1, "max_depth": 2},
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y": 30},
      "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "m"}],
      "lights": [{"type": "point", "position": [0, 0, -3], "intensity": [5, 5, 5]}]})",
                                               "t.json", "."));
  std::vector<float> rgb(300, 0.0f);
  for (int lit = 0; lit < 5; ++lit) rgb[3 * lit + 1] = 0.5f;  // 95 black pixels
  std::string w = BlackImageWarning(scene, rgb, "");
  EXPECT_NE(w.find("95.0% of its pixels"), std::string::npos) << w;
  EXPECT_NE(w.find("no environment: only the scene's 1 light lights it"), std::string::npos) << w;
  rgb[3 * 5] = 0.5f;  // 94 black: no warning
  EXPECT_EQ(BlackImageWarning(scene, rgb, ""), "");
  std::vector<float> dim(300, 1e-4f);  // every pixel just below half an 8-bit level
  w = BlackImageWarning(scene, dim, "");
  EXPECT_NE(w.find("too weak for the 8-bit output (brightest pixel 0.0001)"), std::string::npos)
      << w;
  std::vector<float> visible(300, 2e-4f);  // encodes to one 8-bit level: not black
  EXPECT_EQ(BlackImageWarning(scene, visible, ""), "");
}

}  // namespace
}  // namespace pt::test
