#include "src/app/run.h"

#include <chrono>
#include <cstdio>
#include <new>
#include <optional>
#include <string>

#include "src/app/app_failure.h"
#include "src/app/cli.h"
#include "src/app/outputs.h"
#include "src/app/render_job.h"
#include "src/app/resume.h"
#include "src/app/stats_json.h"
#include "src/app/stop_signals.h"
#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/scene/effects.h"
#include "src/scene/scene_checks.h"

namespace pt {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void Warn(const std::string& warning) {
  std::fprintf(stderr, "pathtracer: warning: %s\n", warning.c_str());
}

SceneDesc LoadAndOverride(const CliOptions& cli, double* loadMs) {
  Clock::time_point start = Clock::now();
  SceneDesc desc;
  try {
    desc = LoadScene(cli.scenePath);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
  *loadMs = MsSince(start);
  try {
    ApplyCliOverrides(cli, &desc.render);
  } catch (const CliError& e) {
    throw AppFailure{kExitBadCommandLine, std::string(e.what()) + " (see --help)"};
  }
  for (const std::string& warning : desc.warnings) Warn(warning);
  return desc;
}

Scene Build(SceneDesc desc, double* bvhBuildMs) {
  Clock::time_point start = Clock::now();
  try {
    Scene scene = BuildScene(std::move(desc));
    // The builder's own BVH time when it keeps one; else the whole build.
    *bvhBuildMs = scene.bvhBuildMs > 0.0 ? scene.bvhBuildMs : MsSince(start);
    return scene;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
}

// The reference at the size of what is rendered: the crop's, or a full image cut to it.
std::vector<float> ReadReference(const CliOptions& cli, const RenderSettings& settings) {
  int width = 0, height = 0;
  std::vector<float> rgb;
  try {
    ReadImageRgb(cli.referencePath, &width, &height, &rgb);
  } catch (const ImageError& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
  CropWindow crop = cli.crop.value_or(CropWindow{0, 0, settings.width, settings.height});
  int cropW = crop.x1 - crop.x0, cropH = crop.y1 - crop.y0;
  if (width == cropW && height == cropH) return rgb;
  if (width != settings.width || height != settings.height) {
    throw AppFailure{kExitBadInput, cli.referencePath + ": the reference is " +
                                        std::to_string(width) + "x" + std::to_string(height) +
                                        ", the render " + std::to_string(cropW) + "x" +
                                        std::to_string(cropH)};
  }
  std::vector<float> cut;
  cut.reserve(size_t(cropW) * cropH * 3);
  for (int y = crop.y0; y < crop.y1; ++y) {
    const float* row = rgb.data() + (size_t(y) * width + crop.x0) * 3;
    cut.insert(cut.end(), row, row + size_t(cropW) * 3);
  }
  return cut;
}

// auto: CUDA when it is built and a GPU is present, else the CPU.
BackendKind ChooseBackend(BackendKind requested, const AppBackends& backends) {
  int gpus = backends.cudaDeviceCount ? backends.cudaDeviceCount() : 0;
  bool cudaReady = backends.cudaSession != nullptr && gpus > 0;
  if (requested == BackendKind::kCuda && !cudaReady) {
    throw AppFailure{kExitRuntimeFailure,
                     backends.cudaSession ? "--backend cuda: no CUDA device found"
                                         : "--backend cuda: this build has no CUDA backend"};
  }
  bool useCuda = requested != BackendKind::kCpu && cudaReady;
  return useCuda ? BackendKind::kCuda : BackendKind::kCpu;
}

RenderOptions MakeRenderOptions(const CliOptions& cli, BackendKind backend,
                                const std::vector<float>* reference) {
  RenderOptions options;
  options.backend = backend;
  options.threads = cli.threads;
  options.compact = cli.compact;
  options.sort = cli.sort;
  options.sortMethod = cli.sortMethod;
  options.integrator = cli.integrator;
  if (cli.crop) options.crop = *cli.crop;
  options.timeLimitSeconds = cli.timeLimitSeconds;
  options.previewEverySeconds = cli.previewEverySeconds;
  options.reference = reference;
  options.maxPathsInFlight = cli.maxPaths;
  options.adaptive = cli.adaptive;
  options.lightPaths = cli.lightPaths;
  options.rayOffsetEpsilon = cli.rayOffsetEpsilon;
  options.filmDouble = cli.filmDouble;
  options.specialize = cli.specialize;
  options.triangleTest = cli.triangleTest;
  options.clampLuminance = cli.clampLuminance;
  // Feature buffers (albedo, normal, depth) go into an --hdr EXR.
  options.featureBuffers = !cli.hdrPath.empty() && IsExrPath(cli.hdrPath);
  return options;
}

// One line saying what the scene needs simulated and which stage variant runs it.
void PrintEffects(const Scene& scene, bool specialize) {
  uint32_t effects = AnalyzeEffects(scene);
  std::string names;
  for (const std::string& n : EffectNames(effects)) names += (names.empty() ? "" : ", ") + n;
  FeatureClass variant = specialize ? ChooseFeatureClass(effects) : FeatureClass::kGeneral;
  std::fprintf(stderr, "pathtracer: effects: %s; stage variant: %s%s\n",
               names.empty() ? "none" : names.c_str(), FeatureClassName(variant),
               specialize ? "" : " (--specialize off)");
}

std::string StopNote(const JobOutcome& job) {
  switch (job.reason) {
    case StopReason::kSignal: return " (stopped by " + SignalName(job.signal) + ")";
    case StopReason::kTimeLimit: return " (stopped by --time-limit)";
    case StopReason::kConverged: return " (adaptive: every pixel converged)";
    default: return "";
  }
}

void PrintSummary(const JobOutcome& job) {
  const RenderStats& s = job.result.stats;
  RenderRates rates = ComputeRates(s);
  std::string device = s.device.empty() ? s.backend : s.backend + ", " + s.device;
  std::fprintf(stderr,
               "pathtracer: %dx%d, %.1f spp in %.3f s on %s: %.2f Msamples/s, %.2f Mrays/s%s\n",
               job.result.image.width, job.result.image.height, s.sppMean, s.renderMs / 1e3,
               device.c_str(), rates.msamplesPerS, rates.mraysPerS, StopNote(job).c_str());
}

// The last lines: each file written.
void PrintWritten(const std::vector<std::string>& files, const CliOptions& cli, bool resumable) {
  for (const std::string& file : files) {
    bool state = resumable && file == cli.hdrPath;
    std::fprintf(stderr, "pathtracer: wrote %s%s\n", file.c_str(),
                 state ? (" (resumable: --resume " + file + " continues it)").c_str() : "");
  }
}

RunReport MakeReport(const CliOptions& cli, const Scene& scene, const JobOutcome& job,
                     BackendKind backend) {
  RunReport r;
  r.commandLine = cli.arguments;
  r.sceneFile = cli.scenePath;
  r.sppRequested = scene.desc.render.spp;
  r.stopReason = StopReasonName(job.reason);
  if (job.reason == StopReason::kSignal) r.signal = SignalName(job.signal);
  r.clampLuminance = cli.clampLuminance;
  r.resumedFrom = cli.resumePath;
  r.resumedSamples = job.resumedSamples;
  r.checkpoints = job.checkpoints;
  r.deviceMemory = backend == BackendKind::kCuda;
  r.peakRssBytes = PeakRssBytes();
  return r;
}

// The render on the chosen backend; with the render's description where a resumable state
// may be written or read.
RenderJob MakeJob(const CliOptions& cli, const Scene& scene, BackendKind backend,
                  const AppBackends& backends, const std::vector<float>* reference) {
  RenderJob job;
  job.cli = &cli;
  job.scene = &scene;
  job.makeSession = backend == BackendKind::kCuda ? backends.cudaSession : backends.cpuSession;
  job.options = MakeRenderOptions(cli, backend, reference);
  if (IsExrPath(cli.hdrPath) || !cli.resumePath.empty()) {
    bool adaptive = cli.adaptive == Toggle::kAuto ? scene.desc.render.adaptive.enabled
                                                  : cli.adaptive == Toggle::kOn;
    job.description = DescribeRender(cli, scene, job.options, adaptive).dump();
  }
  return job;
}

// The images (the --hdr EXR resumable when the job kept its film) and the stats; returns the
// files written.
std::vector<std::string> WriteResults(const CliOptions& cli, const Scene& scene,
                                      const RenderJob& job, const JobOutcome& outcome,
                                      AppTimes times, Clock::time_point start) {
  try {
    ResumableState state{&outcome.film, job.options.filmDouble, job.description};
    std::vector<std::string> written =
        WriteImages(cli, outcome.result.image, outcome.keepState ? &state : nullptr);
    if (!cli.statsJsonPath.empty()) {
      times.totalMs = MsSince(start);
      RunReport report = MakeReport(cli, scene, outcome, job.options.backend);
      WriteStatsJson(cli.statsJsonPath, StatsToJson(outcome.result.stats, scene, times, report));
      written.push_back(cli.statsJsonPath);
    }
    return written;
  } catch (const ImageError& e) {
    throw AppFailure{kExitRuntimeFailure, e.what()};
  }
}

int Run(const CliOptions& cli, const AppBackends& backends, Clock::time_point start) {
  CheckOutputsWritable(cli);
  AppTimes times;
  Scene scene = Build(LoadAndOverride(cli, &times.loadMs), &times.bvhBuildMs);
  for (const std::string& warning : DarkSceneWarnings(scene)) Warn(warning);
  PrintEffects(scene, cli.specialize);
  std::vector<float> reference;
  if (!cli.referencePath.empty()) reference = ReadReference(cli, scene.desc.render);
  BackendKind backend = ChooseBackend(cli.backend, backends);
  RenderJob job = MakeJob(cli, scene, backend, backends, cli.referencePath.empty() ? nullptr : &reference);
  std::optional<FilmState> resumed;
  if (!cli.resumePath.empty()) resumed = LoadResumeFilm(cli, job.description);  // or exit 2
  job.resumeFrom = resumed ? &*resumed : nullptr;
  InstallStopSignals();
  JobOutcome outcome = RunRenderJob(job);
  std::vector<std::string> written = WriteResults(cli, scene, job, outcome, times, start);
  PrintSummary(outcome);
  PrintWritten(written, cli, outcome.keepState);
  return outcome.reason == StopReason::kSignal ? 128 + outcome.signal : kExitOk;
}

// Out of GPU memory: what was asked, and what to lower.
std::string OutOfMemoryMessage(const OutOfDeviceMemory& e, const CliOptions& cli) {
  auto gib = [](size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.2f GiB", double(bytes) / double(1ull << 30));
    return std::string(text);
  };
  std::string paths = cli.maxPaths ? " (now " + std::to_string(cli.maxPaths) + ")" : "";
  return std::string(e.what()) + ": asked for " + gib(e.requestedBytes) + " more with " +
         gib(e.heldBytes) + " held by the renderer; the GPU had " + gib(e.deviceFreeBytes) +
         " free of " + gib(e.deviceTotalBytes) + ". Hint: lower --max-paths" + paths +
         " (the paths in flight, about 120 bytes each), or render a smaller image or --crop";
}

}  // namespace

int RunApp(int argc, const char* const* argv, const AppBackends& backends) {
  Clock::time_point start = Clock::now();
  CliOptions cli;
  try {
    cli = ParseCli(argc, argv);
  } catch (const CliError& e) {
    std::fprintf(stderr, "pathtracer: %s (see --help)\n", e.what());
    return kExitBadCommandLine;
  }
  if (cli.help) {
    std::fputs(CliUsage().c_str(), stdout);
    return kExitOk;
  }
  if (cli.version) {
    std::printf("pathtracer %s\n", PT_VERSION);
    return kExitOk;
  }
  try {
    return Run(cli, backends, start);
  } catch (const AppFailure& failure) {
    std::fprintf(stderr, "pathtracer: %s\n", failure.message.c_str());
    return failure.status;
  } catch (const OutOfDeviceMemory& e) {
    std::fprintf(stderr, "pathtracer: %s\n", OutOfMemoryMessage(e, cli).c_str());
    return kExitRuntimeFailure;
  } catch (const BackendUnavailable& e) {
    std::fprintf(stderr, "pathtracer: %s\n", e.what());
    return kExitRuntimeFailure;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "pathtracer: out of memory\n");
    return kExitRuntimeFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pathtracer: %s\n", e.what());
    return kExitRuntimeFailure;
  }
}

}  // namespace pt
