// --denoise from the command line: -o is the denoised image, the --hdr EXR keeps the raw image
// and gains denoised.R/G/B, the stats hold its time; a --denoise render cannot resume a film
// kept without the half films.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "src/io/exr_codec.h"
#include "src/io/image_io.h"
#include "tests/cli_test_util.h"

namespace pt::test {
namespace {

TEST(DenoiseCli, DenoisesTheOutputAndKeepsTheRawImageInTheHdr) {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string out = dir + "/out.pfm", hdr = dir + "/out.exr", stats = dir + "/stats.json";
  std::string text;
  ASSERT_EQ(RunPathtracer(scene + " --spp 8 --denoise -o " + out + " --hdr " + hdr +
                              " --stats-json " + stats + " --quiet 2>&1", &text), 0) << text;
  EXPECT_NE(text.find("denoised"), std::string::npos) << text;
  ExrFile exr(hdr);
  std::vector<float> r, denoisedR, shown;
  ASSERT_TRUE(exr.Channel("R", &r));
  ASSERT_TRUE(exr.Channel("denoised.R", &denoisedR));
  int w = 0, h = 0;
  ReadImageRgb(out, &w, &h, &shown);
  ASSERT_EQ(shown.size(), 3 * denoisedR.size());
  size_t differing = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    EXPECT_EQ(shown[3 * i], denoisedR[i]);  // -o is the denoised layer
    differing += std::fabs(denoisedR[i] - r[i]) > 1e-6f;
  }
  EXPECT_GT(differing, r.size() / 4);  // the raw beauty is kept beside it
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  ASSERT_TRUE(j["time_ms"].contains("denoise"));
  EXPECT_GT(j["time_ms"]["denoise"].get<double>(), 0.0);
}

TEST(DenoiseCli, WithoutTheFlagNothingChanges) {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string hdr = dir + "/out.exr", stats = dir + "/stats.json";
  ASSERT_EQ(RunPathtracer(scene + " -o " + dir + "/out.png --hdr " + hdr + " --stats-json " +
                          stats + " --quiet"), 0);
  std::vector<float> ignored;
  EXPECT_FALSE(ExrFile(hdr).Channel("denoised.R", &ignored));
  EXPECT_FALSE(nlohmann::json::parse(ReadText(stats))["time_ms"].contains("denoise"));
}

TEST(DenoiseCli, ResumingAFilmWithoutHalvesIsRefused) {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string hdr = dir + "/state.exr";
  ASSERT_EQ(RunPathtracer(scene + " -o " + dir + "/a.png --hdr " + hdr +
                          " --checkpoint-every 1000 --quiet"), 0);
  std::string text;
  EXPECT_EQ(RunPathtracer(scene + " --spp 4 --denoise --resume " + hdr + " -o " + dir +
                              "/b.png --quiet 2>&1", &text), 2);
  EXPECT_NE(text.find("--denoise"), std::string::npos) << text;
}

}  // namespace
}  // namespace pt::test
