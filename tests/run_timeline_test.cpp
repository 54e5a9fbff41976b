// Every millisecond named (issue 28): --stats-json's time_ms cuts the run into parts (process
// start, set-up, load, BVH build, device start, upload, render, output, ...) that add up to its
// total, and the total is the process's wall time as measured around it; the time to the first
// pixel lies inside the run. RunTimeline's own rules are checked on their own first.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "src/app/run_timeline.h"
#include "tests/cli_test_util.h"
#include "tests/test_util.h"

namespace pt {
namespace {

TEST(RunTimeline, MarksAndSplitsCutTheRunIntoPartsThatSumToTheTotal) {
  const auto mainStart = RunTimeline::Clock::now();
  RunTimeline t(mainStart);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  t.Mark("load");
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  t.Mark("job");
  t.Split("job", {{"render", 4.0}, {"upload", 100.0}}, "rest");  // upload takes what is left
  t.Mark("load");  // a name twice: summed
  const auto parts = t.Parts();
  ASSERT_EQ(parts.size(), 5u);
  EXPECT_EQ(parts[0].first, "process_start");
  EXPECT_EQ(parts[1].first, "load");
  EXPECT_EQ(parts[2].first, "render");
  EXPECT_EQ(parts[3].first, "upload");
  EXPECT_EQ(parts[4].first, "rest");
  EXPECT_GE(t.Part("load"), 20.0);
  EXPECT_DOUBLE_EQ(t.Part("render"), 4.0);
  EXPECT_GE(t.Part("upload"), 6.0);
  EXPECT_DOUBLE_EQ(t.Part("rest"), 0.0);
  double sum = 0.0;
  for (const auto& p : parts) sum += p.second;
  EXPECT_NEAR(sum, t.TotalMs(), 1e-9);
  const double sinceMain =
      std::chrono::duration<double, std::milli>(RunTimeline::Clock::now() - mainStart).count();
  EXPECT_NEAR(t.TotalMs() - t.Part("process_start"), sinceMain, 1.0);
  // This test binary started long before this test: its start is that far back.
  EXPECT_GT(t.Part("process_start"), 0.0);
  EXPECT_FALSE(t.FirstPixelMs());
  t.SetFirstPixel(mainStart);
  EXPECT_NEAR(*t.FirstPixelMs(), t.Part("process_start"), 1e-6);
}

// A CPU render of about a second: the parts of time_ms add up to its total, and the total is
// within 2% of the wall time around the process (what is left out: the kernel's exec and the
// exit after the stats are written).
TEST(RunTimeline, StatsPartsAddUpToTheProcessWallTime) {
  const std::string dir = test::TempDir();
  const std::string scene = test::WriteText(dir + "/tiny.json", test::kTinyScene);
  const std::string stats = dir + "/stats.json";
  const std::string args = scene + " -o " + dir + "/out.png --hdr " + dir +
                           "/out.exr --backend cpu --threads 2 --quiet --width 96 --height 96 "
                           "--spp 256 --stats-json " + stats;
  std::string out;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(test::RunPathtracer(args, &out), 0) << out;
  const double wall =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const nlohmann::json j = nlohmann::json::parse(test::ReadText(stats));
  const nlohmann::json& t = j["time_ms"];
  double sum = 0.0;
  std::set<std::string> names;
  for (const std::string name : t["parts"]) {
    ASSERT_TRUE(t.contains(name)) << name;
    ASSERT_GE(t[name].get<double>(), 0.0) << name;
    sum += t[name].get<double>();
    names.insert(name);
  }
  for (const char* name : {"process_start", "setup", "load", "bvh_build", "scene_prep",
                           "device_start", "upload", "render", "film_readback", "teardown",
                           "output", "stats"}) {
    EXPECT_TRUE(names.count(name)) << name;
  }
  const double total = t["total"];
  EXPECT_NEAR(sum, total, 1e-6 * total);
  RecordProperty("wall_ms", std::to_string(wall));
  RecordProperty("total_ms", std::to_string(total));
#if defined(__SANITIZE_ADDRESS__)
  // The leak check at exit runs after the stats: only the order of magnitude here.
  EXPECT_NEAR(total, wall, 0.25 * wall) << out;
#else
  EXPECT_NEAR(total, wall, 0.02 * wall) << out;
#endif
  // The render dominates, and the first pixel is in once the first wave is done.
  EXPECT_GT(t["render"].get<double>(), 0.3 * total);
  const double firstPixel = t["first_pixel"];
  EXPECT_GT(firstPixel, t["process_start"].get<double>() + t["load"].get<double>());
  EXPECT_LT(firstPixel, total);
  EXPECT_TRUE(t["background"].is_object());  // the CPU backend: no device thread
  EXPECT_FALSE(t["background"].contains("device_start"));
}

}  // namespace
}  // namespace pt
