// Long renders on the GPU (skipped without one): a CUDA render stopped by SIGTERM and resumed
// matches the uninterrupted render statistically (and reports whether it is bit-identical),
// with device memory in its stats; running out of GPU memory is exit status 3 with a hint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "src/io/image_io.h"
#include "tests/cli_test_util.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt {
namespace {

// The --hdr EXR as a film image: mean, variance and sample counts.
FilmImage ReadHdr(const std::string& path) {
  FilmImage img;
  ReadExrRgb(path, &img.width, &img.height, &img.rgb);
  size_t n = size_t(img.width) * img.height;
  img.variance.resize(3 * n);
  for (int c = 0; c < 3; ++c) {
    std::vector<float> v = ReadExrChannel(path, std::string("variance.") + "RGB"[c], &img.width,
                                          &img.height);
    for (size_t i = 0; i < n; ++i) img.variance[3 * i + c] = v[i];
  }
  std::vector<float> s = ReadExrChannel(path, "samples", &img.width, &img.height);
  img.samples.assign(s.begin(), s.end());
  return img;
}

TEST(LongRenderGpu, AStoppedAndResumedRenderAgreesWithAnUninterruptedOne) {
  if (!test::HaveGpu()) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  std::string dir = test::TempDir(), out;
  std::string scene = test::SourcePath("scenes/cornell_box.json");
  // Three waves a sample (4096 pixels, 1500 paths): a stop leaves pixels a sample apart.
  std::string base = scene + " --backend cuda --width 64 --height 64 --spp 2048 --max-paths 1500";
  auto outputs = [&](const std::string& name) {
    return " -o " + dir + "/" + name + ".pfm --hdr " + dir + "/" + name + ".exr";
  };
  ASSERT_EQ(test::RunPathtracer(base + outputs("same_seed") + " --quiet", &out), 0) << out;
  ASSERT_EQ(test::RunPathtracer(base + outputs("other_seed") + " --seed 77 --quiet", &out), 0)
      << out;
  ASSERT_EQ(test::RunPathtracerAndSignal(base + outputs("stopped") + " --preview-every 0.2",
                                         dir + "/stopped.pfm", "TERM", &out),
            143)
      << out;
  std::string stats = dir + "/stats.json";
  ASSERT_EQ(test::RunPathtracer(base + outputs("resumed") + " --quiet --resume " + dir +
                                    "/stopped.exr --stats-json " + stats,
                                &out),
            0)
      << out;
  nlohmann::json j = nlohmann::json::parse(test::ReadText(stats));
  EXPECT_GT(j["resumed"]["samples_before"].get<uint64_t>(), 0u);
  EXPECT_LT(j["resumed"]["samples_before"].get<uint64_t>(), 64u * 64u * 2048u);
  EXPECT_EQ(j["memory"]["renderer_buffers_on"], "device");
  EXPECT_GT(j["peak_device_bytes"].get<uint64_t>(), 0u);

  FilmImage resumed = ReadHdr(dir + "/resumed.exr"), other = ReadHdr(dir + "/other_seed.exr");
  for (uint32_t s : resumed.samples) ASSERT_EQ(s, 2048u);
  bool identical = test::ReadText(dir + "/resumed.pfm") == test::ReadText(dir + "/same_seed.pfm");
  std::printf("resumed CUDA render bit-identical to the uninterrupted one: %s\n",
              identical ? "yes" : "no");
  // Against an independent render: z per 8x8 block and channel from the films' variances; at
  // most the binomial bound of blocks beyond the 1% level (false alarm 1e-4).
  int tested = 0, failing = 0;
  for (int by = 0; by < 64; by += 8)
    for (int bx = 0; bx < 64; bx += 8)
      for (int c = 0; c < 3; ++c) {
        test::WindowMean a = test::MeanOverWindow(resumed, c, bx, by, bx + 8, by + 8);
        test::WindowMean b = test::MeanOverWindow(other, c, bx, by, bx + 8, by + 8);
        double sd = std::sqrt(a.varianceOfMean + b.varianceOfMean);
        ++tested;
        if (sd > 0.0 ? std::fabs(a.mean - b.mean) / sd > 2.5758 : a.mean != b.mean) ++failing;
      }
  EXPECT_LE(failing, test::BinomialUpperBound(tested, 0.01, 1e-4)) << failing << " of " << tested;
}

TEST(LongRenderGpu, OutOfGpuMemoryIsExitThreeWithAHint) {
  if (!test::HaveGpu()) GTEST_SKIP() << "no CUDA GPU here: runs on a GPU machine";
  std::string dir = test::TempDir(), out;
  // About 2e9 paths of 120+ bytes: far beyond any GPU's memory.
  std::string args = test::SourcePath("scenes/cornell_box.json") + " -o " + dir +
                     "/out.png --backend cuda --width 8192 --height 8192 --spp 64 "
                     "--max-paths 2000000000 --quiet";
  EXPECT_EQ(test::RunPathtracer(args, &out), 3) << out;
  EXPECT_NE(out.find("pathtracer: out of GPU memory in cudaMalloc: asked for "), std::string::npos)
      << out;
  EXPECT_NE(out.find("Hint: lower --max-paths (now 2000000000)"), std::string::npos) << out;
  EXPECT_EQ(test::ReadText(dir + "/out.png"), "");
}

}  // namespace
}  // namespace pt
