#include "src/app/denoise_step.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "src/app/app_failure.h"

namespace pt {

DenoiseSettings DenoiseSettingsFor(const CliOptions& cli, SamplerKind sampler) {
  DenoiseSettings settings;
  settings.outliers = cli.denoiseOutliers;
  settings.radius = cli.denoiseRadius;
  // Measured (docs/denoise.md): for independent samples the sample variance is as good or
  // better at 16 spp; for Sobol samples it overstates the noise and blurs detail.
  settings.calibrateVariance =
      cli.denoiseCalibrate.value_or(sampler != SamplerKind::kIndependent);
  // Measured too: keeping the seen emission out helped crops of Sobol renders but not the
  // whole 1080p images (a bright light's edge keeps its footprint noise), so it is asked for.
  settings.keepSeenEmission = cli.denoiseKeepEmission.value_or(false);
  return settings;
}

std::unique_ptr<Denoiser> MakeAppDenoiser(const CliOptions& cli, SamplerKind sceneSampler,
                                          BackendKind backend,
                                          const AppBackends& backends, int device) {
  if (!cli.denoise) return nullptr;
  bool cuda = backend == BackendKind::kCuda;
  DenoiserFactory make = cuda ? backends.cudaDenoiser : backends.cpuDenoiser;
  if (!make) throw AppFailure{kExitRuntimeFailure, "--denoise: this build has no denoiser here"};
  try {
    return make(cuda ? device : cli.threads,
                DenoiseSettingsFor(cli, cli.sampler.value_or(sceneSampler)));
  } catch (const BackendUnavailable& e) {
    throw AppFailure{kExitRuntimeFailure, std::string("--denoise: ") + e.what()};
  }
}

void DenoiseImage(Denoiser* denoiser, FilmImage& image, AppTimes* times) {
  if (!denoiser) return;
  try {
    denoiser->Denoise(image);
  } catch (const std::invalid_argument& e) {  // the film lacks what it reads: our bug
    throw AppFailure{kExitRuntimeFailure, std::string("internal: ") + e.what()};
  }
  if (times) times->denoiseMs = std::max(times->denoiseMs, 0.0) + denoiser->LastMs();
  std::fprintf(stderr, "pathtracer: denoised on %s in %.3f s (passes %.1f ms)\n",
               denoiser->BackendName().c_str(), denoiser->LastMs() / 1e3,
               denoiser->LastPassesMs());
}

}  // namespace pt
