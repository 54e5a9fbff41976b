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
    uint64_t total = uint64_t(plan_.cropPixels) * uint64_t(plan_.spp), done = 0;
    for (const WaveInfo& wave : plan_.waves) {
      if (StopRequested()) break;
      RunWave(wave);
      done += wave.PathCount();
      AfterWave(done, total);
    }
    backend_.Synchronize();
    stats_.renderMs = Ms(renderStart_, Clock::now());
    return Finish(done);
  }

  // ---- One wave, bounce by bounce ----
  void RunWave(const WaveInfo& wave) {
    uint32_t n = wave.PathCount();
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

  // Shade: emission, next-event estimation (queues shadow rays), BSDF sampling, roulette.
  void Shade(const WaveInfo& wave, uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    IntegratorParams params = params_;
    const uint32_t* queue = queue_.Data();
    backend_.ParallelFor(Stage::kShade, n, [=] PT_HD(uint32_t i) {
      ShadePath(scene, params, wave, ps, queue[i]);
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
    std::vector<vec3> sum, sumSquares;
    std::vector<uint32_t> count;
    filmSum_.Download(sum);
    filmSumSquares_.Download(sumSquares);
    filmCount_.Download(count);
    return ResolveFilmImage(plan_.cropWidth, plan_.cropHeight, sum, sumSquares, count);
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double Ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  }

  void Allocate();
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
  PathState pathState_{};
  Buffer<vec3> filmSum_, filmSumSquares_;
  Buffer<uint32_t> filmCount_;
  FilmView film_{};
  Buffer<Counter> counters_;

  RenderStats stats_;
  Clock::time_point renderStart_, lastPreview_;
  double lastRelMseLog_ = -1.0;
};

}  // namespace pt

#include "src/integrator/wavefront_impl.h"
