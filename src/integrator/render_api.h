// The renderer as the application sees it: options in, an image and statistics out, with the
// same entry point on each backend. Backends implement RenderCpu / RenderCuda.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/core/rng.h"
#include "src/integrator/shade_queues.h"
#include "src/scene/scene.h"

namespace pt {

enum class BackendKind { kAuto, kCpu, kCuda };
enum class Toggle { kAuto, kOff, kOn };
// Shading order: the queue as it stands; ordered by material key (one kernel); or one kernel
// per shade queue (src/integrator/shade_queues.h).
enum class SortMode { kAuto, kOff, kMaterial, kQueues };
// How a bounce's paths are ordered by key: counting sort (histogram, scan, scatter), radix
// sort over the bits the keys need, or over all 32 bits (the old ordering, for comparison).
enum class SortMethod { kAuto, kCounting, kRadix, kRadixFullWidth };
enum class IntegratorMode { kMis, kBsdf, kNee };
enum class LightPaths { kAll, kDirect, kIndirect };
// The values are SceneView::triangleTest's (shapes.h): kBoxClamped is the watertight test with
// each hit's distance raised to its primitive's box entry (ShapeBoxEntry).
enum class TriangleTest { kWatertight, kMollerTrumbore, kBoxClamped };
enum class EnvSampling { kImportance, kUniform };
// How shadow rays estimate transmittance through grid media (--transmittance; docs/media.md).
enum class TransmittanceMode { kRatio, kDelta };

struct CropWindow {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) x [y0, y1); empty = whole image
  bool Empty() const { return x1 <= x0 || y1 <= y0; }
};

struct RenderOptions {
  BackendKind backend = BackendKind::kAuto;
  int threads = 0;  // CPU threads, 0 = all cores
  Toggle compact = Toggle::kAuto;
  SortMode sort = SortMode::kAuto;
  SortMethod sortMethod = SortMethod::kAuto;
  Toggle rayOrder = Toggle::kAuto;   // sort each bounce's rays before intersect (ray_order.h)
  Toggle primPool = Toggle::kAuto;   // pool a warp's leaf tests (traverse_wide_pooled.h)
  Toggle warmUp = Toggle::kAuto;     // a discarded wave loads the kernels (auto: when lazy)
  IntegratorMode integrator = IntegratorMode::kMis;
  CropWindow crop;
  double timeLimitSeconds = 0.0;     // <= 0: none
  double previewEverySeconds = 0.0;  // <= 0: none
  const std::vector<float>* reference = nullptr;  // linear RGB of the crop/image size, or null
  size_t maxPathsInFlight = 0;       // 0: the backend's default
  LightPaths lightPaths = LightPaths::kAll;
  float rayOffsetEpsilon = 0.0f;     // > 0: a fixed offset instead of error bounds (a study)
  bool filmDouble = false;           // accumulate in double precision
  Toggle adaptive = Toggle::kAuto;   // kAuto: the scene's render.adaptive
  bool specialize = true;            // stage variants specialised to the scene's effects
  TriangleTest triangleTest = TriangleTest::kWatertight;
  bool featureBuffers = false;       // first-hit albedo, normal and depth (for --hdr EXR)
  EnvSampling envSampling = EnvSampling::kImportance;  // how the environment map is sampled
  int device = 0;                    // CUDA device index (an MPI rank's: local rank mod GPUs)
  float clampLuminance = 0.0f;       // > 0: each sample scaled to at most this luminance (biased)
  LightSampler lightSampler = LightSampler::kAuto;  // how next-event estimation picks a light
  TransmittanceMode transmittance = TransmittanceMode::kRatio;  // shadow rays in grid media
  bool halfFilms = false;            // also the even-indexed samples' sum (--denoise's halves)
  std::optional<SamplerKind> sampler;  // the random numbers' source (rng.h); empty: the scene's
};

// The accumulated picture: mean radiance, the variance of each pixel's samples, and counts.
struct FilmImage {
  int width = 0, height = 0;
  std::vector<float> rgb;       // mean, 3 floats per pixel, rows top to bottom
  std::vector<float> variance;  // per-channel sample variance, 3 floats per pixel
  std::vector<uint32_t> samples;
  // First-hit feature buffers, averaged over samples (only when requested).
  std::vector<float> albedo, normal, depth;  // 3, 3 and 1 floats per pixel
  // The mean and count of the even-indexed samples (halfFilms only): with rgb and samples,
  // the two half films of a dual-buffer denoiser.
  std::vector<float> evenRgb;
  std::vector<uint32_t> evenSamples;
  // With the half films (may be empty, meaning none): the means of the emission the camera
  // saw (FilmView::residualMean), over all and over the even samples, and the sample variance
  // of the rest; the denoiser filters the rest and adds the emission back.
  std::vector<float> emission, evenEmission, residualVariance;
  std::vector<float> denoised;  // 3 floats per pixel, when denoised (src/denoise/)
};

// The film's raw per-pixel state over the crop window, enough to continue it exactly: the
// Welford mean and M2 of linear RGB (float films hold float values exactly), the Welford
// luminance statistics adaptive sampling reads, sample counts, and feature sums (empty
// unless feature buffers were requested).
struct FilmState {
  uint32_t width = 0, height = 0;
  std::vector<glm::dvec3> mean, m2;
  std::vector<float> lumMean, lumM2;
  std::vector<uint32_t> count;
  std::vector<vec3> albedoSum, normalSum;
  std::vector<float> depthSum;
  std::vector<vec3> evenSum;          // the even-indexed samples (empty unless halfFilms)
  std::vector<uint32_t> evenCount;
  // With evenSum: the residual's Welford statistics and the seen emission's even sum
  // (FilmView::residualMean).
  std::vector<vec3> residualMean, residualM2, evenEmissionSum;

  size_t PixelCount() const { return size_t(width) * height; }
};

struct StageTimes {
  double generate = 0, intersect = 0, sort = 0, shade = 0, shadow = 0, compact = 0,
         accumulate = 0;
  double medium = 0;  // the medium stage (scenes with participating media)
  std::array<double, kShadeQueueCount> shadeQueues{};  // per queue (--sort queues), in shade
};

struct RenderStats {
  std::string backend, device;
  int threads = 0;
  double renderMs = 0.0, uploadMs = 0.0;
  double warmUpMs = 0.0;  // the discarded wave that loaded the kernels (not in renderMs)
  bool warmedUp = false;
  StageTimes stages;  // milliseconds
  uint64_t samples = 0;
  double sppMean = 0.0;
  uint64_t cameraRays = 0, extensionRays = 0, shadowRays = 0;
  uint64_t nodesVisited = 0, primsTested = 0, traversals = 0;
  uint64_t nonfiniteSamples = 0;
  size_t pathStateBytesPerPath = 0, pathsInFlight = 0, peakDeviceBytes = 0;
  bool interrupted = false;
  bool compactUsed = false;
  bool rayOrderUsed = false;
  bool primPoolUsed = false;
  bool sortUsed = false;
  std::string sortMode = "off";    // the shading order that ran (auto's choice)
  std::string sortMethod;          // how paths were ordered, when they were
  std::string sortReason;          // why auto chose it (the rule, or the calibration)
  uint64_t pathsOrdered = 0;       // paths ordered, summed over bounces
  std::string specialization;  // the stage variant that ran
  std::string lightSampler;    // the light sampler that ran (auto's choice)
  std::string sampler;         // the sampler that drew the random numbers (SamplerKindName)
  std::vector<std::pair<double, double>> referenceRelMse;  // (seconds, relMSE)
};

struct RenderCallbacks {
  std::function<bool()> shouldStop;                     // polled between waves (Ctrl-C)
  std::function<void(const FilmImage&)> onPreview;      // every previewEverySeconds
  std::function<void(uint64_t done, uint64_t total)> onProgress;
  // Polled between bounces: true drops the wave under way (none of its samples reach the
  // film) and ends the render step, as shouldStop does (a live preview's newer edit).
  std::function<bool()> abandonWave;
};

struct RenderResult {
  FilmImage image;
  RenderStats stats;
};

// A backend that cannot run here (not built, no GPU): exit status 3 in the app.
struct BackendUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A device allocation that did not fit: what was asked, what the renderer already held, and
// what the device had free of its total (bytes). Exit status 3 in the app, with a hint.
struct OutOfDeviceMemory : std::runtime_error {
  OutOfDeviceMemory(const std::string& what, size_t requested, size_t held, size_t freeBytes,
                    size_t totalBytes)
      : std::runtime_error(what), requestedBytes(requested), heldBytes(held),
        deviceFreeBytes(freeBytes), deviceTotalBytes(totalBytes) {}
  size_t requestedBytes, heldBytes, deviceFreeBytes, deviceTotalBytes;
};

RenderResult RenderCpu(const Scene& scene, const RenderOptions& options,
                       const RenderCallbacks& callbacks = {});
RenderResult RenderCuda(const Scene& scene, const RenderOptions& options,
                        const RenderCallbacks& callbacks = {});

bool CudaBackendBuilt();
int CudaDeviceCount();      // 0 when not built or no GPU
// Starts GPU localRank % count (driver, context, modules) and returns the count (0: none).
int CudaStartDevice(int localRank);
// Makes the pinned buffers big uploads go through (cuda/staged_upload.cuh) on a thread of its
// own, for GPU localRank % count; returns at once. For a scene known to be big, ahead of its
// upload.
void CudaPrepareUploads(int localRank);
std::string CudaDeviceName();

// relMSE as the CLI contract defines it: mean((x - r)^2 / (r^2 + 1e-2)) over pixels, channels.
double RelMse(const std::vector<float>& image, const std::vector<float>& reference);

}  // namespace pt
