#include "src/app/run_steps.h"

#include <cstdio>
#include <new>

#include "src/app/app_failure.h"
#include "src/app/stop_signals.h"
#include "src/distributed/chunked_render.h"
#include "src/distributed/distributed.h"
#include "src/io/environment_loader.h"
#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/media/media_tables.h"
#include "src/scene/effects.h"
#include "src/scene/energy_compensation.h"

namespace pt {
namespace {

std::string StopNote(const JobOutcome& job) {
  switch (job.reason) {
    case StopReason::kSignal: return " (stopped by " + SignalName(job.signal) + ")";
    case StopReason::kTimeLimit: return " (stopped by --time-limit)";
    case StopReason::kConverged: return " (adaptive: every pixel converged)";
    default: return "";
  }
}

}  // namespace

double MsSince(AppClock::time_point start) {
  return std::chrono::duration<double, std::milli>(AppClock::now() - start).count();
}

void Warn(const std::string& warning) {
  std::fprintf(stderr, "pathtracer: warning: %s\n", warning.c_str());
}

LoadOptions CliLoadOptions(const CliOptions& cli) {
  LoadOptions load;
  load.camera = cli.camera;
  load.animation = cli.animation;
  load.time = cli.time;
  load.variant = cli.variant;
  load.environmentGiven = !cli.envPath.empty();
  return load;
}

SceneDesc LoadAndOverride(const CliOptions& cli, double* loadMs) {
  AppClock::time_point start = AppClock::now();
  SceneDesc desc;
  try {
    desc = LoadScene(cli.scenePath, CliLoadOptions(cli));
    if (cli.envPath == kEnvNone) RemoveEnvironment(&desc);
    else if (!cli.envPath.empty()) ReplaceEnvironmentMap(cli.envPath, &desc);
    if (cli.envStrength) desc.environment.strength = *cli.envStrength;
    if (cli.energyCompensation) EnableEnergyCompensation(&desc);
    if (cli.fogSigmaS) ApplyFog(*cli.fogSigmaS, &desc);
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
  std::string dark = DarkEnvironmentWarning(desc);
  if (!dark.empty()) desc.warnings.push_back(dark);
  for (const std::string& warning : desc.warnings) Warn(warning);
  return desc;
}

// --bvh auto: the wide layout, measured the faster on both backends (benchmarks/RESULTS.md:
// GPU 1.07-1.25x per render; CPU 1.2-1.6x per traced ray).
BvhBuildOptions ChooseBvh(const CliOptions& cli, const AppBackends& backends,
                          DeviceStart* device, int localRank, bool* builtOnDevice) {
  BvhBuildOptions options;
  options.builder = cli.bvhBuilder;
  options.threads = cli.threads;
  options.layout = cli.bvhLayout.value_or(BvhLayout::kWide);
  if (!device || cli.backend == BackendKind::kCpu) return options;
  // A device that fails the build (an error, out of memory) leaves it to the host's threads.
  auto onDevice = [device, localRank, builtOnDevice](auto build, const std::vector<Aabb>& bounds,
                                                     auto* out) {
    const int count = device->DeviceCount();  // waits for the device's start
    bool ok = false;
    try {
      ok = count > 0 && build(bounds, localRank % count, out);
    } catch (const std::exception&) {
      ok = false;
    }
    if (ok && builtOnDevice) *builtOnDevice = true;
    return ok;
  };
  if (auto build = backends.lbvhBuild) {
    options.deviceLbvh = [onDevice, build](const std::vector<Aabb>& bounds, BvhBuildResult* out) {
      return onDevice(build, bounds, out);
    };
  }
  if (auto build = backends.wideLbvhBuild) {
    options.deviceWideLbvh = [onDevice, build](const std::vector<Aabb>& bounds,
                                               WideBvhResult* out) {
      return onDevice(build, bounds, out);
    };
  }
  return options;
}

std::string BuilderThatRan(const CliOptions& cli, bool builtOnDevice) {
  if (builtOnDevice || cli.bvhBuilder == BvhBuilder::kLbvh) return "gpu";
  return cli.bvhBuilder == BvhBuilder::kSbvh ? "sbvh" : "sah";
}

Scene Build(SceneDesc desc, const BvhBuildOptions& bvh, double* bvhBuildMs) {
  AppClock::time_point start = AppClock::now();
  try {
    Scene scene = BuildScene(std::move(desc), bvh);
    // The builder's own BVH time when it keeps one; else the whole build.
    *bvhBuildMs = scene.bvhBuildMs > 0.0 ? scene.bvhBuildMs : MsSince(start);
    return scene;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw AppFailure{kExitBadInput, e.what()};
  }
}

BackendKind ChooseBackend(BackendKind requested, const AppBackends& backends,
                          DeviceStart* started) {
  int gpus = 0;
  if (started && started->BackgroundMs() >= 0.0) gpus = started->DeviceCount();
  else if (backends.cudaDeviceCount) gpus = backends.cudaDeviceCount();
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
  options.rayOrder = cli.rayOrder;
  options.primPool = cli.primPool;
  options.warmUp = cli.warmUp;
  options.envSampling = cli.envSampling;
  options.lightSampler = cli.lightSampler;
  options.sampler = cli.sampler;
  options.transmittance = cli.transmittance;
  options.clampLuminance = cli.clampLuminance;
  // Feature buffers (albedo, normal, depth) go into an --hdr EXR; --denoise reads them and the
  // two half films.
  options.featureBuffers = (!cli.hdrPath.empty() && IsExrPath(cli.hdrPath)) || cli.denoise;
  options.halfFilms = cli.denoise;
  return options;
}

void CheckChunkOptions(const CliOptions& cli, const Scene& scene, const RenderOptions& options,
                       bool distributed) {
  if ((cli.rankTimeoutSeconds || cli.lanes) && !MpiBuilt()) {
    throw AppFailure{kExitBadCommandLine,
                     std::string(cli.lanes ? "--lanes" : "--rank-timeout") +
                         ": this build has no MPI support (no MPI library was found when it "
                         "was configured)"};
  }
  if (!distributed && cli.chunks.value_or(1) <= 1) return;
  int spp = scene.desc.render.spp;
  if (cli.chunks && *cli.chunks > spp) {
    throw AppFailure{kExitBadCommandLine, "--chunks " + std::to_string(*cli.chunks) +
                                              " is more than the " + std::to_string(spp) +
                                              " samples per pixel"};
  }
  std::string where = distributed ? " across MPI ranks" : " with --chunks";
  auto refuse = [&](const std::string& what, const std::string& hint) {
    throw AppFailure{kExitBadCommandLine, what + " is not supported" + where + " yet" + hint};
  };
  if (AdaptiveRequested(scene, options)) refuse("adaptive sampling", ": add --adaptive off");
  if (!cli.referencePath.empty()) refuse("--reference", "");
  if (cli.previewEverySeconds > 0.0) refuse("--preview-every", "");
  // A chunked film is not a per-pixel prefix of the samples, which is what a resume continues.
  if (cli.checkpointEverySeconds > 0.0) refuse("--checkpoint-every", "");
  if (!cli.resumePath.empty()) refuse("--resume", "");
}

void PrintEffects(const Scene& scene, bool specialize) {
  uint32_t effects = AnalyzeEffects(scene);
  std::string names;
  for (const std::string& n : EffectNames(effects)) names += (names.empty() ? "" : ", ") + n;
  FeatureClass variant =
      specialize ? ChooseFeatureClass(effects) : UnspecializedFeatureClass(effects);
  std::fprintf(stderr, "pathtracer: effects: %s; stage variant: %s%s\n",
               names.empty() ? "none" : names.c_str(), FeatureClassName(variant),
               specialize ? "" : " (--specialize off)");
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

}  // namespace pt
