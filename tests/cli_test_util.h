// Helpers for tests that run the built `pathtracer` binary: a tiny scene, files in and out,
// running it in the foreground or in the background to send it signals.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/test_util.h"

namespace pt::test {

// A tiny scene with a diffuse floor and sphere, an area light, a point light and a background.
inline constexpr const char* kTinyScene = R"({
  "render": {"width": 16, "height": 16, "spp": 2, "max_depth": 3, "seed": 1},
  "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov_y": 45},
  "background": [0.1, 0.1, 0.1],
  "materials": {
    "white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
    "lamp": {"type": "emissive", "radiance": [5, 5, 5]}
  },
  "objects": [
    {"type": "quad", "origin": [-1, 0, -1], "u": [0, 0, 2], "v": [2, 0, 0], "material": "white"},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "white"},
    {"type": "quad", "origin": [-0.5, 2, -0.5], "u": [1, 0, 0], "v": [0, 0, 1], "material": "lamp"}
  ],
  "lights": [{"type": "point", "position": [0, 1.5, 1], "intensity": [1, 1, 1]}]
})";

inline std::string WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Runs the binary with arguments; returns its exit status and keeps its output.
inline int RunPathtracer(const std::string& args, std::string* output = nullptr) {
  std::string text;
  int status = RunCommand(BinaryPath("pathtracer") + " " + args, &text);
  if (output) *output = text;
  return status;
}

// Runs the binary in the background, waits (up to 30 s) until `waitFor` exists - a file the
// render writes once it is under way - then sends it `signal` ("TERM", "KILL", ...); returns
// its exit status (128 + the signal when it dies of it or reports it).
inline int RunPathtracerAndSignal(const std::string& args, const std::string& waitFor,
                                  const std::string& signal, std::string* output = nullptr) {
  std::string command = "(" + BinaryPath("pathtracer") + " " + args + " 2>&1 & pid=$!; i=0;" +
                        " while [ ! -f " + waitFor + " ] && [ $i -lt 600 ]; do sleep 0.05;" +
                        " i=$((i+1)); done; kill -" + signal + " $pid; wait $pid)";
  return RunCommand(command, output);
}

// Runs the binary on `scene` (with `extraArgs`) as a bad-input run must end: exit status 2, a
// message naming the scene file, no sanitizer report, the existing `-o` image (dir/kept.png)
// untouched, and no --hdr or --stats-json file written. Leaves dir as it found it.
inline void ExpectRefusedWritingNothing(const std::string& scene, const std::string& extraArgs,
                                        const std::string& dir) {
  namespace fs = std::filesystem;
  std::string kept = dir + "/kept.png", hdr = dir + "/new.exr", stats = dir + "/stats.json";
  WriteText(kept, "old image");
  std::string output;
  int status = RunPathtracer("'" + scene + "' " + extraArgs + " -o " + kept + " --hdr " + hdr +
                                 " --stats-json " + stats + " --backend cpu --threads 1 --quiet",
                             &output);
  std::string name = fs::path(scene).filename().string();
  EXPECT_EQ(status, 2) << name << ": " << output;
  EXPECT_NE(output.find(scene), std::string::npos) << name << ": names no file: " << output;
  EXPECT_EQ(output.find("Sanitizer"), std::string::npos) << name << ": " << output;
  EXPECT_TRUE(ReadText(kept) == "old image") << name << " overwrote the output";
  EXPECT_FALSE(fs::exists(hdr)) << name;
  EXPECT_FALSE(fs::exists(stats)) << name;
  fs::remove(kept);
  fs::remove(hdr);
  fs::remove(stats);
}

}  // namespace pt::test
