// The environment on the command line: --env, --env-strength and --env-sampling parsed and
// refused as cli.md says, and the built binary end to end: --env replaces the scene's
// environment (and a sky's sun), --env-strength scales it, a bad map exits 2 writing nothing,
// a dark map warns, and the statistics name the new effects.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "src/app/cli.h"
#include "tests/cli_parse_util.h"
#include "tests/env_test_util.h"

namespace pt::test {
namespace {

namespace fs = std::filesystem;

TEST(EnvCli, OptionsParse) {
  CliOptions d = Parse({"s.json", "-o", "o.png"});
  EXPECT_TRUE(d.envPath.empty());
  EXPECT_FALSE(d.envStrength);
  EXPECT_EQ(d.envSampling, EnvSampling::kImportance);
  CliOptions o = Parse({"s.json", "-o", "o.png", "--env", "sky.hdr", "--env-strength=0.5",
                        "--env-sampling", "uniform"});
  EXPECT_EQ(o.envPath, "sky.hdr");
  EXPECT_EQ(o.envStrength, 0.5f);
  EXPECT_EQ(o.envSampling, EnvSampling::kUniform);
  EXPECT_EQ(Parse({"s.json", "-o", "o.png", "--env-sampling=importance"}).envSampling,
            EnvSampling::kImportance);
  for (auto [args, message] : std::vector<std::pair<std::vector<const char*>, std::string>>{
           {{"--env-sampling", "alias"}, "bad value for --env-sampling"},
           {{"--env-strength", "-1"}, "bad value for --env-strength"},
           {{"--env-strength", "nan"}, "bad value for --env-strength"},
           {{"--env", ""}, "empty file name"},
           {{"--env"}, "missing value for --env"}}) {
    args.insert(args.begin(), {"s.json", "-o", "o.png"});
    EXPECT_NE(ParseError(args).find(message), std::string::npos) << message;
  }
}

// A sphere under a sky (with its sun) as the scene; maps written beside it.
class EnvCliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_ / "scene.json") << R"({
      "render": {"width": 12, "height": 12, "spp": 4, "max_depth": 2},
      "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y": 30},
      "environment": {"sky": {"sun_elevation": 40, "width": 64}, "strength": 0.01},
      "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "m"}]})";
    WriteMap(dir_ / "grey.pfm", 16, [](int, int) { return vec3(0.25f); });
    WriteMap(dir_ / "black.pfm", 16, [](int, int) { return vec3(0.0f); });
  }
  int Run(const std::string& options, std::string* output) {
    return RunCommand(BinaryPath("pathtracer") + " " + (dir_ / "scene.json") + " -o " +
                          (dir_ / "out.pfm") + " --stats-json " + (dir_ / "stats.json") +
                          " --backend cpu --threads 1 --quiet " + options,
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

TEST_F(EnvCliRun, EnvReplacesTheSkyAndItsSunAndStrengthScales) {
  std::string out;
  ASSERT_EQ(Run("--env " + (dir_ / "grey.pfm"), &out), 0) << out;
  // The corner sees the map: 0.25 x the scene's strength 0.01, which --env keeps.
  EXPECT_FLOAT_EQ(Image()[0], 0.0025f);
  nlohmann::json stats = nlohmann::json::parse(std::ifstream(dir_ / "stats.json"));
  std::vector<std::string> effects = stats["scene"]["effects"];
  EXPECT_NE(std::find(effects.begin(), effects.end(), "environment_map"), effects.end());
  // The sky's sun went with the sky.
  EXPECT_EQ(std::find(effects.begin(), effects.end(), "directional_lights"), effects.end());
  ASSERT_EQ(Run("--env " + (dir_ / "grey.pfm") + " --env-strength 2", &out), 0) << out;
  EXPECT_FLOAT_EQ(Image()[0], 0.5f);
  ASSERT_EQ(Run("--env-sampling uniform", &out), 0) << out;
  stats = nlohmann::json::parse(std::ifstream(dir_ / "stats.json"));
  effects = stats["scene"]["effects"].get<std::vector<std::string>>();
  EXPECT_NE(std::find(effects.begin(), effects.end(), "directional_lights"), effects.end());
}

TEST_F(EnvCliRun, BadMapExitsTwoAndWritesNothing) {
  std::string source = SourcePath("tests/malformed/envmaps/");
  for (std::string map : {dir_ / "absent.exr", source + "nan_texel.pfm", source + "square.pfm",
                          source + "garbage.hdr", dir_ / "grey.png"}) {
    std::string out;
    EXPECT_EQ(Run("--env " + map, &out), 2) << out;
    EXPECT_NE(out.find("--env: "), std::string::npos) << out;
    EXPECT_NE(out.find(fs::path(map).filename().string()), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(dir_ / "out.pfm")) << map;
    EXPECT_FALSE(fs::exists(dir_ / "stats.json")) << map;
  }
}

TEST_F(EnvCliRun, DarkMapWarnsAndRenders) {
  std::string out;
  ASSERT_EQ(Run("--env " + (dir_ / "black.pfm"), &out), 0) << out;
  EXPECT_NE(out.find("the environment is dark"), std::string::npos) << out;
  ASSERT_EQ(Run("--env-strength 0", &out), 0) << out;
  EXPECT_NE(out.find("the environment is dark"), std::string::npos) << out;
  ASSERT_EQ(Run("", &out), 0) << out;
  EXPECT_EQ(out.find("dark"), std::string::npos) << out;
}

}  // namespace
}  // namespace pt::test
