// Renders of a ScriptScene as the command line makes them (src/app/run.cpp): the same backend
// choice, render options, session and statistics document, so an image equals the CLI's for
// the same scene, seed and options. A stop callback polled between waves ends a render early
// (the Python module's KeyboardInterrupt); progressive renders hand out the film after each
// range of samples.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "src/app/run.h"
#include "src/denoise/denoiser.h"
#include "src/scripting/script_options.h"
#include "src/scripting/script_scene.h"

namespace pt {

class ScriptStop;

struct ScriptRequest {
  CliOptions cli;               // the options, as the command line's
  OptionKeywords keywords;      // as given, for the statistics' "command_line"
  bool featureBuffers = true;   // first-hit albedo, normal and depth (the CLI's --hdr EXR has them)
  std::function<bool()> shouldStop;  // polled between waves; true stops the render
};

struct ScriptResult {
  FilmImage image;
  nlohmann::ordered_json stats;  // the --stats-json document
  bool stopped = false;          // shouldStop ended it early
};

// The whole render. Throws AppFailure (status 1: options that do not go together, 3: a backend
// that is not there), CliError, SceneError, BackendUnavailable, OutOfDeviceMemory.
ScriptResult RenderScript(ScriptScene& scene, const ScriptRequest& request,
                          const AppBackends& backends);

// One render taken in steps of samples: every pixel takes samples [done, next) per step, so
// the last step's film equals the whole render's. Adaptive sampling is off (every pixel takes
// the same samples). The scene must not be edited meanwhile (Next throws std::logic_error).
class ProgressiveScript {
 public:
  // `steps`: the sample counts after each step, increasing, the last the render's spp; empty:
  // 1, 2, 4, ... up to spp.
  ProgressiveScript(ScriptScene& scene, ScriptRequest request, const AppBackends& backends,
                    std::vector<uint32_t> steps);
  ~ProgressiveScript();

  // Renders the next step into *out; false when every step was rendered (or a stop ended it).
  bool Next(ScriptResult* out);
  uint32_t Spp() const { return spp_; }

 private:
  ScriptScene& scene_;
  ScriptRequest request_;
  BackendKind backend_ = BackendKind::kCpu;
  std::unique_ptr<ScriptStop> stop_;
  uint64_t pixels_ = 0;
  const Scene* built_ = nullptr;
  uint64_t version_ = 0;
  AppTimes times_;
  std::unique_ptr<RenderSession> session_;
  std::unique_ptr<Denoiser> denoiser_;  // denoise=True: each step's film
  std::vector<uint32_t> steps_;
  size_t next_ = 0;
  uint32_t spp_ = 0;
  bool ended_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pt
