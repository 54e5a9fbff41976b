// --denoise from the command line: -o is the denoised image, the --hdr EXR keeps the raw image
// and gains denoised.R/G/B, the stats hold its time; a --denoise render cannot resume a film
// kept without the half films.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
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

// The tiny scene at 8 spp, denoised with extra options into dir/name: the file's bytes.
struct TinyDenoised {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene) + " --spp 8 --denoise --quiet";
  std::string operator()(const std::string& options, const std::string& name) const {
    EXPECT_EQ(RunPathtracer(scene + options + " -o " + dir + "/" + name), 0) << options;
    return ReadText(dir + "/" + name);
  }
};

// --denoise-radius reaches the denoiser (5 is the default, 3 another image), and a radius out
// of 1..20 is a bad command line (exit 1, the option named, nothing written).
TEST(DenoiseCli, RadiusOptionSetsTheSearchWindow) {
  TinyDenoised image;
  const std::string& scene = image.scene;
  const std::string& dir = image.dir;
  std::string byDefault = image("", "default.pfm");
  EXPECT_EQ(image(" --denoise-radius 5", "r5.pfm"), byDefault);
  EXPECT_NE(image(" --denoise-radius=3", "r3.pfm"), byDefault);
  for (const char* bad : {" --denoise-radius 0", " --denoise-radius 21", " --denoise-radius x"}) {
    std::string text;
    EXPECT_EQ(RunPathtracer(scene + bad + " -o " + dir + "/bad.pfm 2>&1", &text), 1) << bad;
    EXPECT_NE(text.find("--denoise-radius"), std::string::npos) << text;
    EXPECT_FALSE(std::filesystem::exists(dir + "/bad.pfm")) << bad;
  }
}

// A two-valued denoiser option reaches the denoiser: per sampler, the image of its default
// value is the image without the option, and the other value's differs.
void ExpectOptionDefaults(const std::string& option, const std::string& independentDefault,
                          const std::string& sobolDefault, const std::string& other) {
  TinyDenoised image;
  for (const std::string& sampler : {std::string("independent"), std::string("sobol")}) {
    const std::string& byDefault = sampler == "sobol" ? sobolDefault : independentDefault;
    const std::string& notDefault = byDefault == other ? independentDefault : other;
    std::string base = " --sampler " + sampler;
    std::string plain = image(base, sampler + ".pfm");
    EXPECT_EQ(image(base + " " + option + " " + byDefault, sampler + "_d.pfm"), plain)
        << option << " " << byDefault << " with " << sampler;
    EXPECT_NE(image(base + " " + option + "=" + notDefault, sampler + "_o.pfm"), plain)
        << option << " " << notDefault << " with " << sampler;
  }
}

// --denoise-variance: the sample variance for independent samples, calibrated for Sobol ones
// (--sampler or the scene's).
TEST(DenoiseCli, VarianceOptionReachesTheDenoiser) {
  ExpectOptionDefaults("--denoise-variance", "sample", "calibrated", "calibrated");
}

// --denoise-emission: the seen emission (here the background) filtered with the rest whatever
// the sampler; `keep` keeps it out.
TEST(DenoiseCli, EmissionOptionReachesTheDenoiser) {
  ExpectOptionDefaults("--denoise-emission", "filter", "filter", "keep");
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

// The denoiser's stderr lines ("pathtracer: denoised on ..."): how often it ran.
size_t DenoiseRuns(const std::string& text) {
  size_t runs = 0;
  for (size_t at = text.find("denoised on"); at != std::string::npos;
       at = text.find("denoised on", at + 1))
    ++runs;
  return runs;
}

std::vector<float> DenoisedRed(const std::string& exr) {
  std::vector<float> red;
  EXPECT_TRUE(ExrFile(exr).Channel("denoised.R", &red)) << exr;
  return red;
}

// Adaptive batches and chunks merge into one film first; the denoiser runs once, on it.
TEST(DenoiseCli, AdaptiveAndChunkedRendersDenoiseOnceAfterTheMerge) {
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  for (const char* mode : {" --adaptive on --spp 16", " --chunks 4 --spp 8"}) {
    std::string text, hdr = dir + "/out.exr";
    ASSERT_EQ(RunPathtracer(scene + mode + " --denoise --backend cpu -o " + dir + "/out.png" +
                                " --hdr " + hdr + " 2>&1", &text), 0) << text;
    EXPECT_EQ(DenoiseRuns(text), 1u) << mode << "\n" << text;
    std::vector<float> red = DenoisedRed(hdr);
    EXPECT_EQ(red.size(), 16u * 16u) << mode;
  }
}

// Under mpirun only rank 0 denoises, once, the merged film: the same denoised image as one
// process with the same chunks (whose film is the same, bit for bit).
TEST(DenoiseCli, AnMpiJobDenoisesOnceOnRankZeroAsOneProcessDoes) {
#if !defined(PT_MPIEXEC)
  GTEST_SKIP() << "built without MPI";
#else
  if (!std::filesystem::exists(PT_MPIEXEC)) GTEST_SKIP() << "no mpiexec at " << PT_MPIEXEC;
  std::string dir = TempDir();
  std::string scene = WriteText(dir + "/tiny.json", kTinyScene);
  std::string args = scene + " --spp 6 --chunks 6 --denoise --backend cpu --threads 1";
  std::string one, two;
  ASSERT_EQ(RunPathtracer(args + " -o " + dir + "/one.png --hdr " + dir + "/one.exr 2>&1", &one),
            0) << one;
  std::string launcher = std::string(PT_MPIEXEC) + " --oversubscribe" +
                         (geteuid() == 0 ? " --allow-run-as-root" : "") + " -np 2 ";
  ASSERT_EQ(RunCommand(launcher + BinaryPath("pathtracer") + " " + args + " -o " + dir +
                           "/two.png --hdr " + dir + "/two.exr 2>&1", &two), 0) << two;
  EXPECT_EQ(DenoiseRuns(one), 1u) << one;
  EXPECT_EQ(DenoiseRuns(two), 1u) << two;
  std::vector<float> a = DenoisedRed(dir + "/one.exr"), b = DenoisedRed(dir + "/two.exr");
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
#endif
}

}  // namespace
}  // namespace pt::test
