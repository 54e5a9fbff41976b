// Display tone mapping (src/io/tone_mapping.h): plain sRGB clipping stays what PNGs always were,
// the AgX-style curve keeps mid grey, greys grey and order, and rolls bright colours off towards
// white; -o's PNG takes --exposure and --tonemap and is unchanged without them.
#include <gtest/gtest.h>

#include <filesystem>

#include "src/io/image_io.h"
#include "src/io/tone_mapping.h"
#include "tests/cli_test_util.h"

namespace pt::test {
namespace {

TEST(ToneMapping, ClipIsThePngEncodingTimesTheExposure) {
  std::vector<float> rgb = {0.0f, 0.18f, 0.5f, 1.0f, 3.0f, 1e-3f};
  std::vector<uint8_t> plain = DisplayPixels(rgb, DisplaySettings{});
  std::vector<uint8_t> brighter = DisplayPixels(rgb, DisplaySettings{1.0f, ToneMapping::kClip});
  for (size_t i = 0; i < rgb.size(); ++i) {
    EXPECT_EQ(plain[i], LinearToSrgb8(rgb[i])) << i;
    EXPECT_EQ(brighter[i], LinearToSrgb8(2.0f * rgb[i])) << i;
  }
}

TEST(ToneMapping, AgxKeepsMidGreyGreysAndOrder) {
  EXPECT_NEAR(AgxDisplay(vec3(0.18f)).x, 0.46136f, 2e-4f);
  float previous = -1.0f;
  // AgX's published inset rows sum to 1 within 1.4e-4: greys stay grey far below an 8-bit step.
  for (float v = 1e-4f; v < 1e4f; v *= 1.5f) {
    vec3 d = AgxDisplay(vec3(v));
    EXPECT_NEAR(d.x, d.y, 1e-3f) << v;
    EXPECT_NEAR(d.y, d.z, 1e-3f) << v;
    EXPECT_GE(d.x, previous) << v;
    previous = d.x;
  }
  EXPECT_GT(AgxDisplay(vec3(1e4f)).x, 0.97f);   // very bright: white
  EXPECT_LT(AgxDisplay(vec3(1e-4f)).x, 0.05f);  // very dark: black
  EXPECT_EQ(AgxDisplay(vec3(0.0f)), AgxDisplay(vec3(0.0f)));  // no NaN at zero
}

TEST(ToneMapping, AgxRollsBrightColoursOffTowardsWhite) {
  // A red 50 times white: clipping shows pure red; the curve lifts the other channels.
  vec3 hot = AgxDisplay(vec3(50.0f, 0.0f, 0.0f));
  EXPECT_GT(hot.x, 0.9f);
  EXPECT_GT(hot.y, 0.3f);
  EXPECT_GT(hot.z, 0.3f);
  // A dim red stays red: the curve does not wash out colours below the highlights.
  vec3 dim = AgxDisplay(vec3(0.1f, 0.0f, 0.0f));
  EXPECT_GT(dim.x, 2.0f * dim.y);
  ToneMapping t;
  EXPECT_TRUE(ParseToneMapping("agx", &t));
  EXPECT_EQ(t, ToneMapping::kAgx);
  EXPECT_FALSE(ParseToneMapping("aces", &t));
}

TEST(ToneMappingCli, PngTakesExposureAndToneMappingAndIsUnchangedWithout) {
  std::string dir = TempDir() + "/tonemap_cli";
  std::filesystem::create_directories(dir);
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string out;
  auto render = [&](const std::string& name, const std::string& extra) {
    EXPECT_EQ(RunPathtracer(scene + " -o " + dir + "/" + name + " --threads 1 --quiet " + extra, &out), 0)
        << out;
    return ReadText(dir + "/" + name);
  };
  std::string plain = render("plain.png", "");
  EXPECT_EQ(render("clip.png", "--tonemap clip --exposure 0"), plain);
  EXPECT_NE(render("agx.png", "--tonemap agx"), plain);
  EXPECT_NE(render("bright.png", "--exposure 1.5"), plain);
  EXPECT_EQ(RunPathtracer(scene + " -o " + dir + "/x.png --tonemap aces", &out), 1) << out;
  EXPECT_NE(out.find("--tonemap"), std::string::npos) << out;
  EXPECT_EQ(RunPathtracer(scene + " -o " + dir + "/x.png --exposure 99", &out), 1) << out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pt::test
