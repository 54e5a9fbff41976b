#include "src/app/run.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <new>
#include <string>

#include "src/app/cli.h"
#include "src/app/progress.h"
#include "src/app/run_steps.h"
#include "src/app/stats_json.h"
#include "src/distributed/chunked_render.h"
#include "src/distributed/distributed.h"
#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/scene/effects.h"

namespace pt {
namespace app {

std::atomic<bool> gInterrupted{false};

// First Ctrl-C: stop after the current wave and write what has accumulated. Second: die.
extern "C" void OnSigint(int) {
  if (gInterrupted.exchange(true)) {
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
    return;
  }
  const char message[] = "\npathtracer: interrupted; writing the image (Ctrl-C again to quit)\n";
  ssize_t ignored = write(STDERR_FILENO, message, sizeof(message) - 1);
  (void)ignored;
}

void InstallSigintHandler() {
  struct sigaction action = {};
  action.sa_handler = OnSigint;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
}

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void CheckOutputsWritable(const CliOptions& cli) {
  for (const std::string* path :
       {&cli.outputPath, &cli.hdrPath, &cli.statsJsonPath, &cli.sppMapPath}) {
    std::string why;
    if (!path->empty() && !CheckWritable(*path, &why)) {
      throw AppFailure{kExitRuntimeFailure, "cannot write " + *path + ": " + why};
    }
  }
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
  for (const std::string& warning : desc.warnings) {
    std::fprintf(stderr, "pathtracer: warning: %s\n", warning.c_str());
  }
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

void WriteOutputs(const CliOptions& cli, const FilmImage& image) {
  WriteImage(cli.outputPath, image, false);
  if (!cli.hdrPath.empty()) WriteImage(cli.hdrPath, image, true);
  if (!cli.sppMapPath.empty()) WriteSppMap(cli.sppMapPath, image);
}

RenderOptions MakeRenderOptions(const CliOptions& cli, BackendKind backend,
                                const std::vector<float>* reference) {
  RenderOptions options;
  options.backend = backend;
  options.threads = cli.threads;
  options.compact = cli.compact;
  options.sort = cli.sort;
  options.integrator = cli.integrator;
  if (cli.crop) options.crop = *cli.crop;
  options.timeLimitSeconds = cli.timeLimitSeconds;
  options.previewEverySeconds = cli.previewEverySeconds;
  options.reference = reference;
  options.adaptive = cli.adaptive;
  options.lightPaths = cli.lightPaths;
  options.rayOffsetEpsilon = cli.rayOffsetEpsilon;
  options.filmDouble = cli.filmDouble;
  options.specialize = cli.specialize;
  options.triangleTest = cli.triangleTest;
  // Feature buffers (albedo, normal, depth) go into an --hdr EXR.
  options.featureBuffers = !cli.hdrPath.empty() && IsExrPath(cli.hdrPath);
  return options;
}

RenderResult Render(const CliOptions& cli, const Scene& scene, SessionFactory makeSession,
                    const RenderOptions& options) {
  ProgressBar progress(cli.quiet);
  RenderCallbacks callbacks;
  callbacks.shouldStop = [] { return gInterrupted.load(std::memory_order_relaxed); };
  callbacks.onProgress = [&progress](uint64_t done, uint64_t total) {
    progress.Update(done, total);
  };
  if (cli.previewEverySeconds > 0.0) {
    callbacks.onPreview = [&cli](const FilmImage& image) {
      try {
        WriteOutputs(cli, image);
      } catch (const ImageError& e) {  // the final write reports it for good
        std::fprintf(stderr, "\npathtracer: warning: preview not written: %s\n", e.what());
      }
    };
  }
  try {
    RenderResult result =
        cli.chunks.value_or(1) > 1
            ? RenderChunked(makeSession, scene, options, callbacks, uint32_t(*cli.chunks))
            : makeSession(scene, options, callbacks)->Render();
    progress.Finish();
    return result;
  } catch (const BackendUnavailable& e) {
    throw AppFailure{kExitRuntimeFailure, e.what()};
  }
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

void PrintSummary(const RenderResult& result) {
  const RenderStats& s = result.stats;
  RenderRates rates = ComputeRates(s);
  std::string device = s.device.empty() ? s.backend : s.backend + ", " + s.device;
  std::fprintf(stderr,
               "pathtracer: %dx%d, %.1f spp in %.3f s on %s: %.2f Msamples/s, %.2f Mrays/s%s\n",
               result.image.width, result.image.height, s.sppMean, s.renderMs / 1e3,
               device.c_str(), rates.msamplesPerS, rates.mraysPerS,
               s.interrupted ? " (interrupted)" : "");
}

int Run(const CliOptions& cli, const AppBackends& backends) {
  CheckOutputsWritable(cli);
  AppTimes times;
  SceneDesc desc = LoadAndOverride(cli, &times.loadMs);
  Scene scene = Build(std::move(desc), &times.bvhBuildMs);
  PrintEffects(scene, cli.specialize);
  std::vector<float> reference;
  if (!cli.referencePath.empty()) reference = ReadReference(cli, scene.desc.render);
  BackendKind backend = ChooseBackend(cli.backend, backends);
  SessionFactory makeSession =
      backend == BackendKind::kCuda ? backends.cudaSession : backends.cpuSession;
  InstallSigintHandler();
  RenderOptions options =
      MakeRenderOptions(cli, backend, cli.referencePath.empty() ? nullptr : &reference);
  CheckChunkOptions(cli, scene, options, false);
  RenderResult result = Render(cli, scene, makeSession, options);
  bool interrupted = gInterrupted.load();
  result.stats.interrupted = result.stats.interrupted || interrupted;
  try {
    WriteOutputs(cli, result.image);
    if (!cli.statsJsonPath.empty()) {
      WriteStatsJson(cli.statsJsonPath, StatsToJson(result.stats, scene, times));
    }
  } catch (const ImageError& e) {
    throw AppFailure{kExitRuntimeFailure, e.what()};
  }
  PrintSummary(result);
  return interrupted ? kExitInterrupted : kExitOk;
}

}  // namespace app

int RunApp(int argc, const char* const* argv, const AppBackends& backends) {
  if (LauncherWorldSize() != 0) return RunMpiApp(argc, argv, backends);
  return RunProcess(argc, argv, backends);
}

int RunProcess(int argc, const char* const* argv, const AppBackends& backends) {
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
    return app::Run(cli, backends);
  } catch (const app::AppFailure& failure) {
    std::fprintf(stderr, "pathtracer: %s\n", failure.message.c_str());
    return failure.status;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "pathtracer: out of memory\n");
    return kExitRuntimeFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pathtracer: %s\n", e.what());
    return kExitRuntimeFailure;
  }
}

}  // namespace pt
