// What the binary tells its user: progress lines when stderr is not a terminal, the files
// written as the last lines, warnings for scenes that render black for a fixable reason, exact
// messages for non-finite numbers, the firefly clamp marked as biased, and out of GPU memory.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "src/app/run.h"
#include "src/core/math.h"
#include "src/io/image_io.h"
#include "tests/cli_test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using test::ReadText;
using test::RunPathtracer;
using test::WriteText;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class CliMessages : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::TempDir();
    scene_ = WriteText(dir_ + "/tiny.json", test::kTinyScene);
  }
  std::string dir_, scene_;
};

TEST_F(CliMessages, ProgressLinesWhenStderrIsNotATerminal) {
  // stderr is a pipe here: progress comes as lines, at the interval asked for.
  std::string out, args = scene_ + " -o " + dir_ + "/out.png --backend cpu --threads 2 " +
                          "--spp 1500 --max-paths 100";
  ASSERT_EQ(RunPathtracer(args + " --progress-every 0.05", &out), 0) << out;
  std::regex line(R"(pathtracer: \d+\.\d of 1500 spp \(\d+\.\d%\), \d+\.\d\d Msamples/s, )"
                  R"(\d+\.\ds elapsed(, eta \d+\.\ds)?)");
  int progressLines = 0;
  for (const std::string& l : Lines(out)) progressLines += std::regex_match(l, line) ? 1 : 0;
  EXPECT_GE(progressLines, 2) << out;
  EXPECT_NE(out.find("%), "), std::string::npos) << out;
  EXPECT_NE(out.find(", eta "), std::string::npos) << out;
  // --quiet: none; the default interval (10 s) is longer than this (short) render.
  std::string shortRender = scene_ + " -o " + dir_ + "/out.png --backend cpu --spp 20";
  for (const std::string& extra : {std::string(" --progress-every 0.001 --quiet"), std::string()}) {
    ASSERT_EQ(RunPathtracer(shortRender + extra, &out), 0) << out;
    EXPECT_EQ(out.find(" spp ("), std::string::npos) << extra << ": " << out;
  }
}

TEST_F(CliMessages, TheLastLinesNameEachFileWritten) {
  std::string out;
  std::string args = scene_ + " -o " + dir_ + "/out.png --hdr " + dir_ + "/out.exr --spp-map " +
                     dir_ + "/spp.png --stats-json " + dir_ + "/stats.json --backend cpu --quiet";
  ASSERT_EQ(RunPathtracer(args, &out), 0) << out;
  std::vector<std::string> lines = Lines(out);
  ASSERT_GE(lines.size(), 4u) << out;
  std::vector<std::string> last(lines.end() - 4, lines.end());
  EXPECT_EQ(last, (std::vector<std::string>{
                      "pathtracer: wrote " + dir_ + "/out.png", "pathtracer: wrote " + dir_ + "/out.exr",
                      "pathtracer: wrote " + dir_ + "/spp.png",
                      "pathtracer: wrote " + dir_ + "/stats.json"}))
      << out;
}

// A downward lamp the camera sees from above lights the floor below it: no "faces away"
// warning, whichever BVH layout holds the scene (the wide one keeps no binary tree to search).
TEST_F(CliMessages, NoFacesAwayWarningForALampThatLightsTheFloor) {
  std::string text = test::kTinyScene;
  const std::string camera = R"("position": [0, 1, 3])";
  text.replace(text.find(camera), camera.size(), R"("position": [0, 3, 3])");
  std::string scene = WriteText(dir_ + "/above.json", text);
  for (const char* layout : {"wide", "binary"}) {
    std::string out;
    ASSERT_EQ(RunPathtracer(scene + " -o " + dir_ + "/out.png --backend cpu --bvh " + layout,
                            &out), 0) << out;
    EXPECT_EQ(out.find("faces away"), std::string::npos) << layout << ": " << out;
  }
}

// A scene that renders black for a reason the user can fix still renders (exit 0), with a
// warning that says why.
TEST_F(CliMessages, WarningsForScenesThatRenderBlack) {
  struct Case {
    std::string from, to, warning;
  };
  std::string text = test::kTinyScene;
  for (const Case& c : std::vector<Case>{
           // No light: the lamp black, no point light, a black background.
           {R"("radiance": [5, 5, 5])", R"("radiance": [0, 0, 0])", ""},
           // The lamp flipped to face up, away from the floor and the camera.
           {R"("u": [1, 0, 0], "v": [0, 0, 1], "material": "lamp")",
            R"("u": [0, 0, 1], "v": [1, 0, 0], "material": "lamp")",
            "warning: emissive material \"lamp\" faces away from the camera and from all other "
            "geometry"},
       }) {
    std::string edited = text;
    edited.replace(edited.find(c.from), c.from.size(), c.to);
    if (c.warning.empty()) {  // also drop the point light and the background
      edited.replace(edited.find(R"("background": [0.1, 0.1, 0.1],)"), 30, "");
      edited.replace(edited.find(R"("intensity": [1, 1, 1])"), 22, R"("intensity": [0, 0, 0])");
    }
    std::string scene = WriteText(dir_ + "/edited.json", edited), out;
    ASSERT_EQ(RunPathtracer(scene + " -o " + dir_ + "/out.png --backend cpu --quiet", &out), 0)
        << out;
    std::string expected = c.warning.empty()
                               ? "pathtracer: warning: the scene has no light (no emissive "
                                 "material with radiance, no point light with intensity, no "
                                 "sun, a black background or environment): the image will be "
                                 "black"
                               : c.warning;
    EXPECT_NE(out.find(expected), std::string::npos) << out;
  }
  // An OBJ without faces.
  WriteText(dir_ + "/empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  std::string withMesh = text;
  withMesh.replace(withMesh.find("\"objects\": ["), 12,
                   R"("objects": [{"type": "mesh", "file": "empty.obj", "material": "white"},)");
  std::string out, scene = WriteText(dir_ + "/mesh.json", withMesh);
  ASSERT_EQ(RunPathtracer(scene + " -o " + dir_ + "/out.png --backend cpu --quiet", &out), 0)
      << out;
  EXPECT_NE(out.find("pathtracer: warning: empty.obj: the mesh has no triangles"),
            std::string::npos)
      << out;
  // The tiny scene itself draws no warning.
  ASSERT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --backend cpu --quiet", &out), 0);
  EXPECT_EQ(out.find("warning"), std::string::npos) << out;
}

TEST_F(CliMessages, ANonFiniteNumberIsNamedAtItsIndex) {
  std::string text = test::kTinyScene;
  text.replace(text.find("\"look_at\": [0, 0.5, 0]"), 22, "\"look_at\": [0, NaN, 0]");
  std::string scene = WriteText(dir_ + "/nan.json", text), out;
  EXPECT_EQ(RunPathtracer(scene + " -o " + dir_ + "/out.png", &out), 2) << out;
  EXPECT_EQ(out, "pathtracer: " + scene +
                     ": camera.look_at[1]: NaN is not a finite number (JSON has no NaN or "
                     "Infinity)\n");
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
}

float MaxLuminance(const std::string& pfm) {
  int w = 0, h = 0;
  std::vector<float> rgb;
  ReadPfmRgb(pfm, &w, &h, &rgb);
  float most = 0.0f;
  for (size_t i = 0; i < rgb.size(); i += 3) {
    most = std::max(most, Luminance(vec3(rgb[i], rgb[i + 1], rgb[i + 2])));
  }
  return most;
}

// --clamp: no pixel's mean exceeds the clamp (each sample was scaled to it at most), and the
// stats say the estimate is biased.
TEST_F(CliMessages, TheFireflyClampIsAppliedAndMarkedBiased) {
  std::string out, base = scene_ + " --backend cpu --threads 2 --quiet --spp 16";
  ASSERT_EQ(RunPathtracer(base + " -o " + dir_ + "/free.pfm", &out), 0) << out;
  float brightest = MaxLuminance(dir_ + "/free.pfm");
  ASSERT_GT(brightest, 0.1f);
  float clamp = 0.25f * brightest;
  std::string stats = dir_ + "/stats.json";
  ASSERT_EQ(RunPathtracer(base + " -o " + dir_ + "/clamped.pfm --clamp " + std::to_string(clamp) +
                              " --stats-json " + stats,
                          &out),
            0)
      << out;
  EXPECT_LE(MaxLuminance(dir_ + "/clamped.pfm"), clamp * (1.0f + 1e-5f));
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  EXPECT_EQ(j["biased"], true);
  EXPECT_NEAR(j["clamp_luminance"].get<double>(), clamp, 1e-6 * clamp);
}

// Out of GPU memory, as the app reports it: a session factory that fails as a device would.
std::unique_ptr<RenderSession> OutOfMemorySession(const Scene&, const RenderOptions&,
                                                  const RenderCallbacks&) {
  throw OutOfDeviceMemory("out of GPU memory in cudaMalloc", 3ull << 30, 70ull << 30,
                          1ull << 29, 80ull << 30);
}
int OneGpu() { return 1; }

TEST_F(CliMessages, OutOfGpuMemorySaysWhatWasAskedAndWhatToLower) {
  AppBackends backends;
  backends.cpuSession = &OutOfMemorySession;
  backends.cudaSession = &OutOfMemorySession;
  backends.cudaDeviceCount = &OneGpu;
  std::string out = dir_ + "/out.png";
  std::vector<const char*> argv = {"pathtracer", scene_.c_str(), "-o", out.c_str(),
                                   "--backend", "cuda", "--max-paths", "4000000", "--quiet"};
  ::testing::internal::CaptureStderr();
  int status = RunApp(int(argv.size()), argv.data(), backends);
  std::string message = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(status, 3);
  EXPECT_NE(message.find("pathtracer: out of GPU memory in cudaMalloc: asked for 3.00 GiB more "
                         "with 70.00 GiB held by the renderer; the GPU had 0.50 GiB free of "
                         "80.00 GiB. Hint: lower --max-paths (now 4000000)"),
            std::string::npos)
      << message;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace pt
