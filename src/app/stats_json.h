// The --stats-json file of ../shared/cli.md: render statistics, scene facts, phase times, and
// what the run was (version, command line, scene file, why it stopped, where it resumed from).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/app/run_timeline.h"
#include "src/integrator/render_api.h"

namespace pt {

// Times measured by the app around the renderer, in milliseconds.
struct AppTimes {
  double loadMs = 0.0;
  double bvhBuildMs = 0.0;
  double totalMs = 0.0;  // the whole run, from the start of the program to the stats
  double denoiseMs = -1.0;  // --denoise's time (copies to and from a GPU included); < 0: none
  // The run cut into named parts (run_timeline.h): when set, time_ms lists them, total is
  // their sum, and first_pixel is reported.
  const RunTimeline* timeline = nullptr;
  double deviceStartBackgroundMs = -1.0;  // the device's start-up off the main thread (>= 0)
  // The builder that made the BVH (bvh.builder: sah, sbvh, gpu; empty: not reported) and
  // whether the GPU built it (bvh.built_on: "device" or "host").
  std::string bvhBuilder;
  bool bvhOnDevice = false;
};

// What the app knows of the run beyond the renderer's statistics.
struct RunReport {
  std::vector<std::string> commandLine;
  std::string sceneFile;
  int sppRequested = 0;
  std::string stopReason = "completed";  // completed, time_limit, signal, converged, failed
  std::string signal;                    // "SIGTERM" when stopped by one, else empty
  float clampLuminance = 0.0f;           // > 0: the firefly clamp (a biased estimate)
  std::string resumedFrom;               // the --resume file, or empty
  uint64_t resumedSamples = 0;           // samples the film held when resumed
  int checkpoints = 0;                   // resumable states written during the render
  bool deviceMemory = false;             // the renderer's buffers live on a GPU
  size_t peakRssBytes = 0;               // the process's peak resident set
};

// Millions of samples and of rays (camera, extension, shadow) per second of render time.
struct RenderRates {
  double msamplesPerS = 0.0, mraysPerS = 0.0;
};
RenderRates ComputeRates(const RenderStats& stats);

// The effects the scene uses: material types present ("diffuse", "emissive", "conductor",
// "dielectric", "plastic"), "absorption", "area_lights", "point_lights", "background_light",
// "depth_of_field". Only materials some primitive uses count.
std::vector<std::string> SceneEffectNames(const Scene& scene);

// The process's peak resident set size in bytes (getrusage), 0 where unknown.
size_t PeakRssBytes();

// The whole document: exactly the keys of the schema, in its order.
nlohmann::ordered_json StatsToJson(const RenderStats& stats, const Scene& scene,
                                   const AppTimes& times, const RunReport& run);

// Writes the document through a temporary file and a rename; throws ImageError on failure.
void WriteStatsJson(const std::string& path, const nlohmann::ordered_json& document);

}  // namespace pt
