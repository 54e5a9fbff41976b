// The wavefront path tracer, generic over the backend. Per wave of paths: generate camera
// rays; then per bounce: intersect, sort by material (optional), shade (queuing shadow rays),
// trace shadow rays, compact finished paths (optional); finally accumulate into the film.
// The Backend supplies memory (Buffer<T>), ParallelFor, and the queue primitives (compaction,
// sort, count); every stage body it runs is the same src/integrator/stages/ function.
//
// Stage launchers are public members because nvcc's extended lambdas may not live in
// private member functions; lambdas copy what they need, never `this` (a host pointer).
#pragma once

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include "src/integrator/film.h"
#include "src/integrator/path_state.h"
#include "src/integrator/render_api.h"
#include "src/integrator/scene_upload.h"
#include "src/integrator/stage_id.h"
#include "src/integrator/stages/accumulate.h"
#include "src/integrator/stages/generate.h"
#include "src/integrator/stages/intersect.h"
#include "src/integrator/stages/shade.h"
#include "src/integrator/stages/shadow.h"
#include "src/integrator/wave_plan.h"

namespace pt {

template <typename Backend>
class WavefrontIntegrator {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  WavefrontIntegrator(Backend& backend, const Scene& scene, const RenderOptions& options,
                      const RenderCallbacks& callbacks, bool compact, bool sort)
      : backend_(backend), scene_(scene), options_(options), callbacks_(callbacks),
        compact_(compact), sort_(sort),
        plan_(MakeWavePlan(scene.desc.render, options.crop, backend.DefaultPathsInFlight(),
                           options.maxPathsInFlight)) {}

  RenderResult Render() {
    auto t0 = Clock::now();
    Allocate();
    stats_.uploadMs = Ms(t0, Clock::now());
    renderStart_ = lastPreview_ = Clock::now();
    uint64_t done = adaptive_.enabled ? RenderAdaptive() : RenderWaves(plan_.waves, 0);
    backend_.Synchronize();
    stats_.renderMs = Ms(renderStart_, Clock::now());
    return Finish(done);
  }

  // Runs waves until done or told to stop; returns the samples taken.
  uint64_t RenderWaves(const std::vector<WaveInfo>& waves, uint64_t done) {
    uint64_t total = uint64_t(plan_.cropPixels) * uint64_t(plan_.spp);
    for (const WaveInfo& wave : waves) {
      if (StopRequested()) break;
      RunWave(wave);
      done += wave.PathCount();
      AfterWave(done, total);
    }
    return done;
  }

  // Adaptive sampling: batches of samples for the pixels still active; after each batch,
  // once pixels have min_spp samples, those whose luminance error bound is under the
  // tolerance leave the active list (compacted like the path queue), and take no more paths.
  uint64_t RenderAdaptive() {
    uint32_t active = plan_.cropPixels, batch = uint32_t(std::max(1, adaptive_.batch));
    uint64_t done = 0;
    for (uint32_t start = 0; start < plan_.spp && active > 0 && !stopped_;) {
      uint32_t count = std::min(batch, plan_.spp - start);
      std::vector<WaveInfo> waves;
      AppendWaves(plan_.base, activePixels_.Data(), active, start, count, plan_.maxPaths, waves);
      done = RenderWaves(waves, done);
      start += count;
      if (start >= uint32_t(adaptive_.minSpp)) active = RetireConverged(active);
    }
    return done;
  }

  // Keeps the pixels whose 95% error bound on mean luminance still exceeds the tolerance.
  uint32_t RetireConverged(uint32_t active) {
    const float* lumMean = film_.lumMean;
    const float* lumM2 = film_.lumM2;
    const uint32_t* count = film_.sampleCount;
    float tolerance = adaptive_.tolerance;
    return backend_.Partition(Stage::kCompact, activePixels_.Data(), active,
                              [=] PT_HD(uint32_t p) {
                                float n = float(count[p]);
                                float variance = n > 1.0f ? lumM2[p] / (n - 1.0f) : 0.0f;
                                float bound = 1.96f * sqrtf(variance / n);
                                return bound > tolerance * fmaxf(lumMean[p], 1e-4f);
                              });
  }

  // ---- One wave, bounce by bounce ----
  void RunWave(const WaveInfo& wave) {
    uint32_t n = wave.PathCount();
    if (n > queue_.Size()) throw std::logic_error("wave larger than the path buffers");
    GenerateCameraRays(wave);
    stats_.cameraRays += n;
    uint32_t alive = n;
    for (int bounce = 0; alive > 0; ++bounce) {
      if (bounce > 0) stats_.extensionRays += alive;
      IntersectClosest(n);
      if (sort_) SortByMaterial(n);
      Shade(wave, n);
      TraceShadowRays(n);
      if (compact_) alive = n = CompactFinished(n);
      else alive = CountAlive(n);
    }
    Accumulate(wave);
    backend_.Synchronize();
  }

  // Initialise: the active pixel list starts as every pixel of the crop window.
  void ResetActivePixels() {
    uint32_t* pixels = activePixels_.Data();
    backend_.ParallelFor(Stage::kGenerate, plan_.cropPixels,
                         [=] PT_HD(uint32_t i) { pixels[i] = i; });
  }

  // Generate: a camera ray per slot; the queue starts as every slot in order.
  void GenerateCameraRays(const WaveInfo& wave) {
    PathState ps = pathState_;
    uint32_t* queue = queue_.Data();
    Camera cam = sceneBuffers_.view.camera;
    backend_.ParallelFor(Stage::kGenerate, wave.PathCount(), [=] PT_HD(uint32_t i) {
      GenerateCameraPath(cam, wave, ps, i);
      queue[i] = i;
    });
  }

  // Intersect: closest hit per queued path, and its material as the sort key.
  void IntersectClosest(uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    const uint32_t* queue = queue_.Data();
    uint32_t* keys = sort_ ? sortKeys_.Data() : nullptr;
    Counter* counters = counters_.Data();
    backend_.ParallelFor(Stage::kIntersect, n, [=] PT_HD(uint32_t i) {
      IntersectPath(scene, ps, queue[i], keys ? keys + i : nullptr, counters);
    });
  }

  // Sort: reorder the queue by material so neighbouring threads shade alike.
  void SortByMaterial(uint32_t n) {
    backend_.SortByKey(Stage::kSort, sortKeys_.Data(), queue_.Data(), n);
  }

  // Shade: emission, next-event estimation (queues shadow rays), BSDF sampling, roulette;
  // in the variant compiled for the scene's effects.
  void Shade(const WaveInfo& wave, uint32_t n) {
    switch (featureClass_) {
      case FeatureClass::kDiffuse: ShadeVariant<FeatureClass::kDiffuse>(wave, n); break;
      case FeatureClass::kSmooth: ShadeVariant<FeatureClass::kSmooth>(wave, n); break;
      default: ShadeVariant<FeatureClass::kGeneral>(wave, n); break;
    }
  }

  template <FeatureClass C>
  void ShadeVariant(const WaveInfo& wave, uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    IntegratorParams params = params_;
    const uint32_t* queue = queue_.Data();
    backend_.ParallelFor(Stage::kShade, n, [=] PT_HD(uint32_t i) {
      ShadePath<C>(scene, params, wave, ps, queue[i]);
    });
  }

  // Shadow: any-hit test for each queued shadow ray.
  void TraceShadowRays(uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    const uint32_t* queue = queue_.Data();
    Counter* counters = counters_.Data();
    backend_.ParallelFor(Stage::kShadow, n, [=] PT_HD(uint32_t i) {
      TraceShadowRay(scene, ps, queue[i], counters);
    });
  }

  // Compact: keep only live paths in the queue.
  uint32_t CompactFinished(uint32_t n) {
    const uint32_t* flags = pathState_.flags;
    return backend_.Partition(Stage::kCompact, queue_.Data(), n,
                              [=] PT_HD(uint32_t id) { return IsAlive(flags[id]); });
  }

  uint32_t CountAlive(uint32_t n) {
    const uint32_t* flags = pathState_.flags;
    return backend_.CountIf(Stage::kCompact, queue_.Data(), n,
                            [=] PT_HD(uint32_t id) { return IsAlive(flags[id]); });
  }

  // Accumulate: each pixel adds its samples of this wave, in sample order.
  void Accumulate(const WaveInfo& wave) {
    PathState ps = pathState_;
    FilmView film = film_;
    Counter* counters = counters_.Data();
    backend_.ParallelFor(Stage::kAccumulate, wave.pixelCount, [=] PT_HD(uint32_t i) {
      AccumulatePixel(wave, ps, film, i, counters);
    });
  }

  // The film as an image: mean and per-channel sample variance per pixel.
  FilmImage ResolveFilm() {
    FilmData data;
    if (options_.filmDouble) {
      filmMeanDouble_.Download(data.mean);
      filmM2Double_.Download(data.m2);
    } else {
      std::vector<vec3> mean, m2;
      filmMean_.Download(mean);
      filmM2_.Download(m2);
      data.mean.assign(mean.begin(), mean.end());
      data.m2.assign(m2.begin(), m2.end());
    }
    filmCount_.Download(data.count);
    if (params_.featureBuffers) {
      filmAlbedo_.Download(data.albedoSum);
      filmNormal_.Download(data.normalSum);
      filmDepth_.Download(data.depthSum);
    }
    return ResolveFilmImage(plan_.cropWidth, plan_.cropHeight, data);
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double Ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  }

  void Allocate();
  void AllocatePaths(size_t n);
  void AllocateFilm(size_t pixels);
  bool StopRequested();
  void AfterWave(uint64_t done, uint64_t total);
  RenderResult Finish(uint64_t samplesDone);

  Backend& backend_;
  const Scene& scene_;
  RenderOptions options_;
  RenderCallbacks callbacks_;
  bool compact_, sort_;
  WavePlan plan_;
  IntegratorParams params_{};
  SceneBuffers<Backend> sceneBuffers_;

  Buffer<vec3> rayOrigin_, rayDir_, throughput_, radiance_, shadowOrigin_, shadowDir_,
      shadowRadiance_;
  Buffer<float> prevPdf_, shadowTMax_;
  Buffer<uint32_t> flags_, queue_, sortKeys_;
  Buffer<HitRecord> hit_;
  Buffer<vec3> featureAlbedo_, featureNormal_;
  Buffer<float> featureDepth_;
  PathState pathState_{};
  Buffer<vec3> filmMean_, filmM2_, filmAlbedo_, filmNormal_;
  Buffer<glm::dvec3> filmMeanDouble_, filmM2Double_;
  Buffer<float> filmLumMean_, filmLumM2_, filmDepth_;
  Buffer<uint32_t> filmCount_, activePixels_;
  FilmView film_{};
  AdaptiveSettings adaptive_;
  FeatureClass featureClass_ = FeatureClass::kGeneral;
  bool stopped_ = false;
  Buffer<Counter> counters_;

  RenderStats stats_;
  Clock::time_point renderStart_, lastPreview_;
  double lastRelMseLog_ = -1.0;
};

}  // namespace pt

#include "src/integrator/wavefront_impl.h"
