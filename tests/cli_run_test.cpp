// The built `pathtracer` binary end to end: each exit status of cli.md (0, 1, 2, 3, 128+N),
// what is and is not written in each case, and the --stats-json schema.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "src/integrator/render_api.h"
#include "src/io/image_io.h"
#include "tests/cli_test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

using test::kTinyScene;
using test::ReadText;
using test::RunPathtracer;
using test::WriteText;

class CliRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::TempDir();
    scene_ = WriteText(dir_ + "/tiny.json", kTinyScene);
  }
  std::string dir_, scene_;
};

TEST_F(CliRun, RendersAndExitsZero) {
  std::string out;
  std::string args = scene_ + " -o " + dir_ + "/out.png --hdr " + dir_ +
                     "/out.exr --backend cpu --threads 2 --quiet";
  ASSERT_EQ(RunPathtracer(args, &out), 0) << out;
  EXPECT_NE(out.find("samples/s"), std::string::npos) << out;  // the summary line
  std::string png = ReadText(dir_ + "/out.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  int w = 0, h = 0;
  std::vector<float> rgb;
  ReadExrRgb(dir_ + "/out.exr", &w, &h, &rgb);
  EXPECT_EQ(w, 16);
  EXPECT_EQ(h, 16);
  std::vector<float> samples = ReadExrChannel(dir_ + "/out.exr", "samples", &w, &h);
  for (float s : samples) EXPECT_EQ(s, 2.0f);
  EXPECT_NO_THROW(ReadExrChannel(dir_ + "/out.exr", "variance.G", &w, &h));
  // Only the outputs: no temporary or probe file is left beside them.
  size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++entries;
  EXPECT_EQ(entries, 3u);
}

TEST_F(CliRun, OverridesReachTheImage) {
  std::string out;
  std::string args = scene_ + " -o " + dir_ + "/out.pfm --width=8 --height 4 --spp 1 " +
                     "--max-depth 0 --seed 7 --rr-depth off --backend cpu";
  ASSERT_EQ(RunPathtracer(args, &out), 0) << out;
  EXPECT_EQ(ReadText(dir_ + "/out.pfm").substr(0, 11), "PF\n8 4\n-1.0");
}

TEST_F(CliRun, HelpAndVersionExitZero) {
  std::string out;
  EXPECT_EQ(RunPathtracer("--help", &out), 0);
  EXPECT_NE(out.find("usage: pathtracer"), std::string::npos) << out;
  EXPECT_EQ(RunPathtracer("--version", &out), 0);
  EXPECT_EQ(out, std::string("pathtracer ") + PT_VERSION + "\n");
}

// A build for x86-64-v3 started on a CPU without it exits 3 with a message instead of dying of
// SIGILL (src/core/host_isa_guard.cpp; the variable stands in for the older CPU). A baseline
// build has no such check and runs.
TEST_F(CliRun, AnX8664V3BuildOnAnOlderCpuExitsThreeSayingWhy) {
  std::string out;
  const std::string args = scene_ + " -o " + dir_ + "/out.png --backend cpu";
#ifdef PT_HOST_ISA_V3
  EXPECT_EQ(RunPathtracer("--version", &out), 0) << out;
  EXPECT_EQ(test::RunCommand("PT_TEST_PRETEND_OLD_CPU=1 " + test::BinaryPath("pathtracer") + " " + args, &out),
            3);
  EXPECT_NE(out.find("needs an x86-64-v3 CPU"), std::string::npos) << out;
  EXPECT_NE(out.find("-DPT_HOST_ISA=baseline"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
#else
  EXPECT_EQ(test::RunCommand("PT_TEST_PRETEND_OLD_CPU=1 " + test::BinaryPath("pathtracer") + " " + args, &out),
            0) << out;
#endif
}

TEST_F(CliRun, BadCommandLineExitsOne) {
  std::string out;
  std::string o = " -o " + dir_ + "/out.png";
  EXPECT_EQ(RunPathtracer(scene_ + o + " --bogus", &out), 1);
  EXPECT_NE(out.find("--help"), std::string::npos) << out;
  EXPECT_EQ(RunPathtracer(scene_, &out), 1) << out;                        // no -o
  EXPECT_EQ(RunPathtracer(scene_ + o + " --spp x", &out), 1) << out;       // bad number
  EXPECT_EQ(RunPathtracer(scene_ + o + " --backend gpu", &out), 1) << out;  // bad enum
  EXPECT_EQ(RunPathtracer(scene_ + o + " --sort-method quick", &out), 1) << out;  // bad enum
  EXPECT_NE(out.find("--sort-method"), std::string::npos) << out;
  EXPECT_EQ(RunPathtracer(scene_ + o + " --crop 0 0 17 4", &out), 1) << out;  // outside 16x16
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
}

TEST_F(CliRun, BadSceneExitsTwoAndWritesNothing) {
  std::string out;
  std::string bad = WriteText(dir_ + "/bad.json", "{ \"render\": { \"width\": 16, ");
  std::string kept = WriteText(dir_ + "/kept.png", "old image");
  std::string args = bad + " -o " + kept + " --hdr " + dir_ + "/new.exr --stats-json " + dir_ +
                     "/stats.json";
  EXPECT_EQ(RunPathtracer(args, &out), 2) << out;
  EXPECT_NE(out.find("bad.json"), std::string::npos) << out;  // the message names the file
  EXPECT_EQ(ReadText(kept), "old image");
  EXPECT_FALSE(fs::exists(dir_ + "/new.exr"));
  EXPECT_FALSE(fs::exists(dir_ + "/stats.json"));
  EXPECT_EQ(RunPathtracer(dir_ + "/missing.json -o " + dir_ + "/new.png", &out), 2) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/new.png"));
}

TEST_F(CliRun, BadReferenceExitsTwo) {
  std::string out;
  std::string wrongSize = dir_ + "/wrong.pfm";
  FilmImage image;
  image.width = 3;
  image.height = 5;
  image.rgb.assign(3 * 5 * 3, 0.5f);
  WriteImage(wrongSize, image);
  EXPECT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --reference " + wrongSize, &out), 2)
      << out;
  EXPECT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --reference " + dir_ + "/no.exr",
                          &out),
            2)
      << out;
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
}

TEST_F(CliRun, UnwritableOutputExitsThreeBeforeLoading) {
  std::string out;
  EXPECT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/no/such/out.png", &out), 3) << out;
  EXPECT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --stats-json " + dir_ +
                              "/no/such/stats.json",
                          &out),
            3)
      << out;
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
  // Checked before the scene is read: a missing scene does not hide the unwritable output.
  EXPECT_EQ(RunPathtracer(dir_ + "/missing.json -o " + dir_ + "/no/out.png", &out), 3) << out;
  if (fs::is_directory("/proc")) {  // not writable even for root
    EXPECT_EQ(RunPathtracer(scene_ + " -o /proc/pt_out.png", &out), 3) << out;
  }
}

TEST_F(CliRun, BackendCudaWithoutGpuExitsThree) {
  if (CudaDeviceCount() > 0) GTEST_SKIP() << "a GPU is present";
  std::string out;
  EXPECT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --backend cuda", &out), 3) << out;
  EXPECT_FALSE(fs::exists(dir_ + "/out.png"));
}

// --bvh and --bvh-build reach the build (the stats name the layout and the builder that ran;
// auto is wide, and sah for a small scene), and the image does not depend on them: the closest
// hit is a property of the scene, not of the tree. The linear BVH (gpu) runs on the host's
// threads on the CPU backend.
TEST_F(CliRun, BvhOptionsChangeTheTreeNotTheImage) {
  std::string reference;
  const char* variants[] = {"", " --bvh binary", " --bvh wide --bvh-build sbvh",
                            " --bvh=binary --bvh-build=sbvh", " --bvh-build gpu",
                            " --bvh binary --bvh-build gpu"};
  const char* layouts[] = {"wide", "binary", "wide", "binary", "wide", "binary"};
  const char* builders[] = {"sah", "sah", "sbvh", "sbvh", "gpu", "gpu"};
  for (int v = 0; v < 6; ++v) {
    std::string out, stats = dir_ + "/stats.json", image = dir_ + "/out.exr";
    ASSERT_EQ(RunPathtracer(scene_ + " -o " + image + " --backend cpu --quiet --stats-json " +
                                stats + variants[v], &out), 0) << variants[v] << ": " << out;
    nlohmann::json j = nlohmann::json::parse(ReadText(stats));
    EXPECT_EQ(j["bvh"]["layout"], layouts[v]) << variants[v];
    EXPECT_EQ(j["bvh"]["builder"], builders[v]) << variants[v];
    EXPECT_EQ(j["bvh"]["built_on"], "host") << variants[v];
    std::string pixels = ReadText(image);
    if (v == 0) reference = pixels;
    EXPECT_TRUE(pixels == reference) << variants[v];
    fs::remove(stats);
    fs::remove(image);
  }
}

TEST_F(CliRun, StatsJsonHasEveryKeyOfTheSchema) {
  std::string out;
  std::string stats = dir_ + "/stats.json";
  ASSERT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --backend cpu --stats-json=" + stats,
                          &out),
            0)
      << out;
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  for (const char* key :
       {"version", "command_line", "scene_file", "backend", "device", "threads", "scene",
        "time_ms", "spp_requested", "samples", "spp_mean", "stop_reason", "signal",
        "interrupted", "resumed", "checkpoints_written", "clamp_luminance", "biased", "rays",
        "msamples_per_s", "mrays_per_s", "bvh", "path_state_bytes_per_path", "paths_in_flight",
        "memory", "peak_device_bytes", "nonfinite_samples", "reference_relmse", "sampler"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["version"], PT_VERSION);
  std::vector<std::string> commandLine = j["command_line"];
  ASSERT_EQ(commandLine.size(), 7u);
  EXPECT_EQ(commandLine[0], test::BinaryPath("pathtracer"));
  EXPECT_EQ(commandLine[1], scene_);
  EXPECT_EQ(commandLine[6], "--stats-json=" + stats);
  EXPECT_EQ(j["scene_file"], scene_);
  EXPECT_EQ(j["spp_requested"], 2);
  EXPECT_EQ(j["stop_reason"], "completed");
  EXPECT_TRUE(j["signal"].is_null());
  EXPECT_TRUE(j["resumed"].is_null());
  EXPECT_EQ(j["checkpoints_written"], 0);
  EXPECT_TRUE(j["clamp_luminance"].is_null());
  EXPECT_EQ(j["biased"], false);
  // Memory that means something on the CPU: the renderer's host buffers and the process.
  EXPECT_EQ(j["memory"]["renderer_buffers_on"], "host");
  EXPECT_GT(j["memory"]["renderer_buffers_peak_bytes"].get<uint64_t>(), 16u * 16u * 2u * 100u);
  EXPECT_GT(j["memory"]["process_peak_rss_bytes"].get<uint64_t>(),
            j["memory"]["renderer_buffers_peak_bytes"].get<uint64_t>());
  EXPECT_TRUE(j["peak_device_bytes"].is_null());  // no device on the CPU backend
  // The whole run's wall time holds every phase.
  double total = j["time_ms"]["total"];
  EXPECT_GE(total, j["time_ms"]["render"].get<double>() + j["time_ms"]["load"].get<double>());
  for (const char* key :
       {"triangles", "primitives", "lights", "textures", "texture_bytes", "effects"}) {
    EXPECT_TRUE(j["scene"].contains(key)) << key;
  }
  for (const char* key : {"total", "load", "bvh_build", "upload", "render", "stages"}) {
    EXPECT_TRUE(j["time_ms"].contains(key)) << key;
  }
  for (const char* key :
       {"generate", "intersect", "sort", "shade", "shadow", "compact", "accumulate"}) {
    EXPECT_TRUE(j["time_ms"]["stages"].contains(key)) << key;
  }
  for (const char* key : {"camera", "extension", "shadow"}) EXPECT_TRUE(j["rays"].contains(key));
  for (const char* key : {"nodes", "mean_nodes_visited", "mean_prims_tested"}) {
    EXPECT_TRUE(j["bvh"].contains(key)) << key;
  }
  EXPECT_EQ(j["backend"], "cpu");
  EXPECT_EQ(j["samples"], 16 * 16 * 2);
  EXPECT_DOUBLE_EQ(j["spp_mean"].get<double>(), 2.0);
  EXPECT_EQ(j["rays"]["camera"], 16 * 16 * 2);
  EXPECT_EQ(j["interrupted"], false);
  EXPECT_EQ(j["scene"]["primitives"], 3);
  std::vector<std::string> effects = j["scene"]["effects"];
  for (const char* effect : {"diffuse", "emissive", "area_lights", "point_lights",
                             "background_light"}) {
    EXPECT_NE(std::find(effects.begin(), effects.end(), effect), effects.end()) << effect;
  }
  EXPECT_TRUE(j["reference_relmse"].is_array());
  EXPECT_EQ(j["sampler"], "independent");
}

// --sampler sobol renders another image of the scene and the statistics say so; a sampler
// the renderer does not know is a command-line error that writes nothing.
TEST_F(CliRun, SamplerOptionReachesTheRenderAndTheStats) {
  std::string out;
  const std::string stats = dir_ + "/stats.json";
  const std::string base = scene_ + " --backend cpu --threads 2 --quiet --stats-json " + stats;
  ASSERT_EQ(RunPathtracer(base + " -o " + dir_ + "/independent.pfm", &out), 0) << out;
  ASSERT_EQ(RunPathtracer(base + " -o " + dir_ + "/sobol.pfm --sampler sobol", &out), 0) << out;
  EXPECT_EQ(nlohmann::json::parse(ReadText(stats))["sampler"], "sobol");
  EXPECT_NE(ReadText(dir_ + "/sobol.pfm"), ReadText(dir_ + "/independent.pfm"));
  fs::remove(stats);
  EXPECT_EQ(RunPathtracer(base + " -o " + dir_ + "/bad.pfm --sampler halton", &out), 1) << out;
  EXPECT_NE(out.find("bad value for --sampler: 'halton' (expected independent|sobol)"),
            std::string::npos)
      << out;
  EXPECT_FALSE(fs::exists(dir_ + "/bad.pfm"));
  EXPECT_FALSE(fs::exists(stats));
  for (const char* f : {"/independent.pfm", "/sobol.pfm"}) fs::remove(dir_ + f);
}

TEST_F(CliRun, ReferenceRelMseIsLogged) {
  std::string out;
  std::string reference = dir_ + "/reference.exr";
  ASSERT_EQ(RunPathtracer(scene_ + " -o " + reference + " --backend cpu --spp 8", &out), 0) << out;
  std::string stats = dir_ + "/stats.json";
  ASSERT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --backend cpu --reference " +
                              reference + " --stats-json " + stats,
                          &out),
            0)
      << out;
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  ASSERT_TRUE(j["reference_relmse"].is_array());
  ASSERT_FALSE(j["reference_relmse"].empty());
  double last = -1.0;
  for (const auto& point : j["reference_relmse"]) {  // labelled points in time order
    ASSERT_TRUE(point.is_object()) << point;
    EXPECT_GE(point["relmse"].get<double>(), 0.0);
    EXPECT_GT(point["seconds"].get<double>(), last);
    last = point["seconds"];
  }
}

TEST_F(CliRun, TimeLimitStopsTheRenderAndWrites) {
  std::string out;
  std::string stats = dir_ + "/stats.json";
  auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(RunPathtracer(scene_ + " -o " + dir_ + "/out.png --backend cpu --spp 10000000 " +
                              "--time-limit 0.5 --stats-json " + stats,
                          &out),
            0)
      << out;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 30.0);
  EXPECT_TRUE(fs::exists(dir_ + "/out.png"));
  nlohmann::json j = nlohmann::json::parse(ReadText(stats));
  EXPECT_LT(j["spp_mean"].get<double>(), 10000000.0);
  EXPECT_EQ(j["stop_reason"], "time_limit");
  EXPECT_EQ(j["interrupted"], true);
  EXPECT_TRUE(j["signal"].is_null());
}

// Each stop signal (a terminal's Ctrl-C, a scheduler's SIGTERM, a closed session's SIGHUP),
// sent to a real process once its render is under way: the image so far, a resumable --hdr
// EXR and the stats marked with the signal are written, and the exit status is 128 + N.
TEST_F(CliRun, EachStopSignalWritesTheImageAndExits128PlusN) {
  for (auto [name, number] : {std::pair{"INT", 2}, {"TERM", 15}, {"HUP", 1}}) {
    SCOPED_TRACE(name);
    std::string image = dir_ + "/" + name + ".png", hdr = dir_ + "/" + name + ".exr",
                stats = dir_ + "/" + name + ".json", out;
    // The first preview on disk says the render runs, however loaded the machine.
    std::string args = scene_ + " -o " + image + " --hdr " + hdr + " --stats-json " + stats +
                       " --backend cpu --spp 10000000 --time-limit 60 --preview-every 0.1";
    ASSERT_EQ(test::RunPathtracerAndSignal(args, image, name, &out), 128 + number) << out;
    ASSERT_TRUE(fs::exists(stats)) << out;  // written after the signal, so not killed by it
    nlohmann::json j = nlohmann::json::parse(ReadText(stats));
    EXPECT_EQ(j["stop_reason"], "signal");
    EXPECT_EQ(j["signal"], std::string("SIG") + name);
    EXPECT_EQ(j["interrupted"], true);
    EXPECT_GT(j["samples"].get<uint64_t>(), 0u);
    EXPECT_NE(out.find(std::string("SIG") + name + " received"), std::string::npos) << out;
    EXPECT_NE(out.find("wrote " + hdr + " (resumable"), std::string::npos) << out;
    int w = 0, h = 0;
    EXPECT_NO_THROW(ReadExrChannel(hdr, "state.mean.R", &w, &h));
    EXPECT_TRUE(fs::exists(image));
  }
}

}  // namespace
}  // namespace pt
