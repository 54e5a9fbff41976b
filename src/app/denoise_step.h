// --denoise in the app: the denoiser of the render's backend, run once on the final image
// (after an MPI job's films are merged, on rank 0) and on each preview.
#pragma once

#include <memory>

#include "src/app/cli.h"
#include "src/app/run.h"
#include "src/app/stats_json.h"

namespace pt {

// The denoiser's settings the options ask for (--denoise-outliers, -radius, -variance) for
// samples drawn by `sampler`, the one in force (--sampler, else the scene's render.sampler; the
// preview's page may change it): without --denoise-variance the variance is calibrated for
// Sobol samples only (docs/denoise.md).
DenoiseSettings DenoiseSettingsFor(const CliOptions& cli, SamplerKind sampler);

// The denoiser --denoise asks for on this backend (device: the CUDA device), or null without
// --denoise. Throws AppFailure (exit 3) when the backend cannot make one.
std::unique_ptr<Denoiser> MakeAppDenoiser(const CliOptions& cli, SamplerKind sceneSampler,
                                          BackendKind backend,
                                          const AppBackends& backends, int device);

// image.denoised := the denoised image; its time is added to times (when given). A denoiser
// that fails is an AppFailure (exit 3).
void DenoiseImage(Denoiser* denoiser, FilmImage& image, AppTimes* times);

}  // namespace pt
