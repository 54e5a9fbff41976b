#include "src/app/run_steps.h"

#include <chrono>
#include <cstdio>
#include <new>

#include "src/app/app_failure.h"
#include "src/io/image_io.h"
#include "src/io/scene_loader.h"

namespace pt {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

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

}  // namespace pt
