#include "src/app/run.h"

#include <chrono>
#include <cstdio>
#include <new>
#include <optional>
#include <string>

#include "src/app/app_failure.h"
#include "src/app/device_start.h"
#include "src/app/cli.h"
#include "src/app/denoise_step.h"
#include "src/app/outputs.h"
#include "src/app/render_job.h"
#include "src/app/resume.h"
#include "src/app/run_steps.h"
#include "src/app/run_timeline.h"
#include "src/app/serve.h"
#include "src/app/stats_json.h"
#include "src/app/stop_signals.h"
#include "src/distributed/distributed.h"
#include "src/io/image_io.h"
#include "src/scene/scene_checks.h"

namespace pt {
namespace {

// Triangles from which a GPU run readies its upload's pinned buffers ahead (~300 MB of arrays).
constexpr size_t kPrepareUploadsTriangles = size_t(1) << 21;

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

// The render on the chosen backend; with the render's description where a resumable state
// may be written or read.
RenderJob MakeJob(const CliOptions& cli, const Scene& scene, BackendKind backend,
                  const AppBackends& backends, const std::vector<float>* reference) {
  RenderJob job;
  job.cli = &cli;
  job.scene = &scene;
  job.makeSession = backend == BackendKind::kCuda ? backends.cudaSession : backends.cpuSession;
  job.options = MakeRenderOptions(cli, backend, reference);
  job.chunks = uint32_t(cli.chunks.value_or(1));
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
                                      AppTimes times, RunTimeline& timeline) {
  try {
    ResumableState state{&outcome.film, job.options.filmDouble, job.description};
    std::vector<std::string> written =
        WriteImages(cli, outcome.result.image, outcome.keepState ? &state : nullptr);
    timeline.Mark("output");
    if (!cli.statsJsonPath.empty()) {
      RunReport report = MakeReport(cli, scene, outcome, job.options.backend);
      timeline.Mark("stats");
      times.timeline = &timeline;
      times.totalMs = timeline.TotalMs();
      WriteStatsJson(cli.statsJsonPath, StatsToJson(outcome.result.stats, scene, times, report));
      written.push_back(cli.statsJsonPath);
    }
    return written;
  } catch (const ImageError& e) {
    throw AppFailure{kExitRuntimeFailure, e.what()};
  }
}

// The render job's part of the timeline cut into the session's start-up (the device's), its
// upload, kernel warm-up and render, the freeing of the session, and the rest (film readback
// and resolve).
void SplitJobTime(const JobOutcome& outcome, RunTimeline& timeline) {
  const RenderStats& stats = outcome.result.stats;
  timeline.Split("render_job",
                 {{"device_start", outcome.sessionMs}, {"upload", stats.uploadMs},
                  {"warm_up", stats.warmUpMs}, {"render", stats.renderMs},
                  {"teardown", outcome.teardownMs}},
                 "film_readback");
  if (outcome.firstPixel) timeline.SetFirstPixel(*outcome.firstPixel);
}

int Run(const CliOptions& cli, const AppBackends& backends, AppClock::time_point start) {
  RunTimeline timeline(start);
  CheckOutputsWritable(cli);
  DeviceStart device(backends, cli.backend);  // beside the loading and the BVH build
  timeline.Mark("setup");
  AppTimes times;
  SceneDesc desc = LoadAndOverride(cli, &times.loadMs);
  timeline.Mark("load");
  // A big scene's upload goes through pinned buffers, made beside its preparation.
  if (backends.prepareUploads && cli.backend != BackendKind::kCpu &&
      desc.triangles.size() >= kPrepareUploadsTriangles)
    backends.prepareUploads(0);
  Scene scene = Build(std::move(desc), ChooseBvh(cli, backends, &device, 0, &times.bvhOnDevice),
                      &times.bvhBuildMs);
  times.bvhBuilder = BuilderThatRan(cli, times.bvhOnDevice);
  timeline.Mark("build");
  timeline.Split("build", {{"bvh_build", times.bvhBuildMs}}, "scene_prep");
  for (const std::string& warning : DarkSceneWarnings(scene)) Warn(warning);
  PrintEffects(scene, cli.specialize);
  std::vector<float> reference;
  if (!cli.referencePath.empty()) reference = ReadReference(cli, scene.desc.render);
  timeline.Mark("scene_prep");
  BackendKind backend = ChooseBackend(cli.backend, backends, &device);
  timeline.Mark("device_start");
  times.deviceStartBackgroundMs = device.BackgroundMs();
  RenderJob job = MakeJob(cli, scene, backend, backends, cli.referencePath.empty() ? nullptr : &reference);
  CheckChunkOptions(cli, scene, job.options, false);
  std::optional<FilmState> resumed;
  if (!cli.resumePath.empty()) resumed = LoadResumeFilm(cli, job.description);  // or exit 2
  job.resumeFrom = resumed ? &*resumed : nullptr;
  std::unique_ptr<Denoiser> denoiser =
      MakeAppDenoiser(cli, scene.desc.render.sampler, backend, backends, 0);
  job.denoiser = denoiser.get();
  InstallStopSignals();
  timeline.Mark("setup");
  JobOutcome outcome = RunRenderJob(job);
  timeline.Mark("render_job");
  if (outcome.result.stats.samples > 0) {
    std::string black = BlackImageWarning(scene, outcome.result.image.rgb,
                                          cli.envPath == kEnvNone ? "--env none" : "");
    if (!black.empty()) Warn(black);
  }
  SplitJobTime(outcome, timeline);
  DenoiseImage(denoiser.get(), outcome.result.image, &times);
  if (denoiser) timeline.Mark("denoise");  // a part of its own: time_ms.denoise
  std::vector<std::string> written = WriteResults(cli, scene, job, outcome, times, timeline);
  PrintSummary(outcome);
  PrintWritten(written, cli, outcome.keepState);
  return outcome.reason == StopReason::kSignal ? 128 + outcome.signal : kExitOk;
}

}  // namespace

int RunApp(int argc, const char* const* argv, const AppBackends& backends) {
  if (LauncherWorldSize() != 0) return RunMpiApp(argc, argv, backends);
  return RunProcess(argc, argv, backends);
}

int RunProcess(int argc, const char* const* argv, const AppBackends& backends) {
  AppClock::time_point start = AppClock::now();
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
    return cli.servePort ? Serve(cli, backends) : Run(cli, backends, start);
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
