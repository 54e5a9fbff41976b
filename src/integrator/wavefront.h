// The wavefront path tracer, generic over the backend. Per wave of paths: generate camera
// rays; then per bounce: intersect, shade (in the order --sort asks: src/integrator/
// shade_launcher.h; queuing shadow rays),
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
#include <type_traits>
#include <vector>

#include "src/integrator/film.h"
#include "src/integrator/film_buffers.h"
#include "src/integrator/media_pass.h"
#include "src/integrator/flag_policy.h"
#include "src/integrator/path_state.h"
#include "src/integrator/render_api.h"
#include "src/integrator/scene_upload.h"
#include "src/integrator/shade_launcher.h"
#include "src/integrator/stage_id.h"
#include "src/integrator/stages/accumulate.h"
#include "src/integrator/stages/generate.h"
#include "src/integrator/stages/intersect.h"
#include "src/integrator/stages/ray_order.h"
#include "src/integrator/stages/shade.h"
#include "src/integrator/stages/shadow.h"
#include "src/integrator/wave_plan.h"
#include "src/lights/light_bvh_build.h"

namespace pt {

template <typename Backend>
class WavefrontIntegrator {
 public:
  template <typename T>
  using Buffer = typename Backend::template Buffer<T>;

  WavefrontIntegrator(Backend& backend, const Scene& scene, const RenderOptions& options,
                      const RenderCallbacks& callbacks)
      : backend_(backend), scene_(scene), options_(options), callbacks_(callbacks),
        plan_(MakeWavePlan(scene.desc.render, options.crop, backend.DefaultPathsInFlight(),
                           options.maxPathsInFlight)) {
    ApplyOptions(options);
  }

  // The whole render: adaptive batches, or every pixel up to spp from its own count.
  RenderResult Render() {
    uint64_t done = Timed([&] { return adaptive_.enabled ? RenderAdaptive() : UpTo(plan_.spp); });
    return Finish(done);
  }

  // Samples [begin, end) for every pixel of the crop (a RenderSession range).
  uint64_t RenderRange(uint32_t begin, uint32_t end) {
    return Timed([&] {
      std::vector<WaveInfo> waves;
      if (end > begin)
        AppendWaves(plan_.base, nullptr, plan_.cropPixels, begin, end - begin, PathCapacity(),
                    waves);
      filmFresh_ = false;
      return RenderWaves(waves, 0, uint64_t(plan_.cropPixels) * (end > begin ? end - begin : 0));
    });
  }

  // Samples [begin, end) of a coarse image of width x height pixels (at most the crop's
  // pixel count, same field of view) into the film's first width x height entries, as a film
  // of that width: a live preview's quick frames while the view moves. The caller resets the
  // film before and after.
  uint64_t RenderCoarse(uint32_t width, uint32_t height, uint32_t begin, uint32_t end) {
    if (width == 0 || height == 0 || uint64_t(width) * height > plan_.cropPixels)
      throw std::invalid_argument("a coarse image must be no larger than the film");
    return Timed([&] {
      WaveInfo base = plan_.base;
      base.cropX0 = base.cropY0 = 0;
      base.cropWidth = base.imageWidth = width;
      base.imageHeight = height;
      std::vector<WaveInfo> waves;
      uint32_t pixels = width * height, count = end > begin ? end - begin : 0;
      if (count > 0) AppendWaves(base, nullptr, pixels, begin, count, PathCapacity(), waves);
      filmFresh_ = false;
      return RenderWaves(waves, 0, uint64_t(pixels) * count);
    });
  }

  uint64_t RenderUpTo(uint32_t spp) {
    return Timed([&] { return UpTo(spp); });
  }

  // Each pixel from its own sample count up to spp: pixels grouped by count (one group on a
  // fresh film, two after an interruption between waves), each group's samples in order, so
  // the film ends bit-identical to an uninterrupted render.
  uint64_t UpTo(uint32_t spp) {
    if (filmFresh_) {
      filmFresh_ = false;
      std::vector<WaveInfo> waves;
      AppendWaves(plan_.base, nullptr, plan_.cropPixels, 0, spp, PathCapacity(), waves);
      return RenderWaves(waves, 0, uint64_t(plan_.cropPixels) * spp);
    }
    std::vector<uint32_t> counts, order;
    filmArrays_.Counts().Download(counts);
    for (uint32_t p = 0; p < counts.size(); ++p)
      if (counts[p] < spp) order.push_back(p);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return counts[a] < counts[b]; });
    uint64_t total = 0;
    for (uint32_t p : order) total += spp - counts[p];
    resumePixels_.Upload(order);
    std::vector<WaveInfo> waves;
    for (size_t g = 0; g < order.size();) {
      size_t e = g;
      while (e < order.size() && counts[order[e]] == counts[order[g]]) ++e;
      uint32_t from = counts[order[g]];
      AppendWaves(plan_.base, resumePixels_.Data() + g, uint32_t(e - g), from, spp - from,
                  PathCapacity(), waves);
      g = e;
    }
    return RenderWaves(waves, 0, total);
  }

  // Runs waves until done or told to stop; returns `done` plus the samples taken.
  uint64_t RenderWaves(const std::vector<WaveInfo>& waves, uint64_t done, uint64_t total) {
    for (const WaveInfo& wave : waves) {
      if (StopRequested()) break;
      if (!RunWave(wave)) {  // abandoned: nothing of it reached the film
        stats_.interrupted = stopped_ = true;
        break;
      }
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
    uint64_t done = 0, total = uint64_t(plan_.cropPixels) * plan_.spp;
    filmFresh_ = false;
    for (uint32_t start = 0; start < plan_.spp && active > 0 && !stopped_;) {
      uint32_t count = std::min(batch, plan_.spp - start);
      std::vector<WaveInfo> waves;
      AppendWaves(plan_.base, activePixels_.Data(), active, start, count, PathCapacity(), waves);
      done = RenderWaves(waves, done, total);
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
  // False when RenderCallbacks::abandonWave dropped it between bounces (not accumulated).
  bool RunWave(const WaveInfo& wave) {
    uint32_t n = wave.PathCount();
    if (n > queue_.Size()) throw std::logic_error("wave larger than the path buffers");
    GenerateCameraRays(wave);
    stats_.cameraRays += n;
    uint32_t alive = n;
    for (int bounce = 0; alive > 0; ++bounce) {
      if (bounce > 0) stats_.extensionRays += alive;
      // The order rays are traced in: sorted by ray (--ray-order; camera rays are in pixel order
      // already), or the queue's. Shading keeps the queue's slot order, where the path state
      // is read contiguously, unless it sorts by material (whose keys follow the traced order).
      const uint32_t* traced = bounce > 0 && rayOrder_ ? OrderRays(n) : queue_.Data();
      IntersectClosest(traced, n);
      if (media_.Active()) SampleMedia(wave, traced, n);
      Shade(wave, sortMode_ == SortMode::kOff ? queue_.Data() : traced, n);
      // Every path is at depth `bounce` here, and shading ends each one at maxDepth before it
      // queues a light sample: after the last bounce there is nothing to trace or compact.
      if (bounce >= params_.maxDepth) break;
      if (callbacks_.abandonWave && callbacks_.abandonWave()) {
        backend_.Synchronize();
        return false;
      }
      // Shadow rays leave the hit points of the rays just traced: in the traced order, rays that
      // arrived together leave together towards the same lights.
      TraceShadowRays(wave, traced, n);
      if (compact_) alive = n = CompactFinished(n);
      else alive = CountAlive(n);
    }
    Accumulate(wave);
    backend_.Synchronize();
    return true;
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

  // Ray order: a copy of the queue sorted by each ray's key (finished paths last).
  const uint32_t* OrderRays(uint32_t n) {
    if (rayQueue_.Size() != queue_.Size()) {
      for (Buffer<uint32_t>* b : {&rayKeys_, &rayKeysOut_, &rayQueue_}) b->Resize(queue_.Size());
      backend_.ReserveOrdering(
          OrderShape{SortMethod::kRadix, kRayOrderKeyBits, 0, uint32_t(queue_.Size())});
    }
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    const uint32_t* queue = queue_.Data();
    uint32_t* keys = rayKeys_.Data();
    backend_.ParallelFor(Stage::kSort, n, [=] PT_HD(uint32_t i) {
      const uint32_t id = queue[i];
      keys[i] = IsAlive(ps.flags[id]) ? RayOrderKey(scene, ps.rayOrigin[id], ps.rayDir[id])
                                      : kRayOrderDeadKey;
    });
    uint32_t* ordered = rayQueue_.Data();
    backend_.OrderByKey(Stage::kSort, OrderShape{SortMethod::kRadix, kRayOrderKeyBits, 0, n},
                        OrderArrays{keys, queue, rayKeysOut_.Data(), ordered});
    return ordered;
  }

  // Intersect: closest hit per queued path, and its sort key when shading is ordered.
  void IntersectClosest(const uint32_t* queue, uint32_t n) {
    ForTraversal([&](auto layout, auto instanced, auto hitTest, auto pooled) {
      IntersectLayout<decltype(layout)::value, decltype(instanced)::value,
                      decltype(hitTest)::value, decltype(pooled)::value>(queue, n);
    });
  }

  // Calls f(layout, instanced, hitTest, pooled) with the scene's traversal variant as
  // std::integral_constant values: each variant is a kernel of its own, a flat scene runs the
  // single-level one, and one whose materials ask for no hit test (alpha, culling) runs it
  // without that code, instanced or not. pooled: a flat scene's wide walk with --prim-pool
  // (traverse_wide_pooled.h), in kernels of its own so that the per-ray walk keeps its
  // registers (10 variants).
  template <typename F>
  void ForTraversal(F f) {
    using Yes = std::true_type;
    using No = std::false_type;
    auto withHitTest = [&](auto layout, auto instanced, auto pooled) {
      hitTests_ ? f(layout, instanced, Yes{}, pooled) : f(layout, instanced, No{}, pooled);
    };
    ForSceneStructure(sceneBuffers_.view, [&](auto layout, auto instanced) {
      if constexpr (decltype(layout)::value == BvhLayout::kWide && !decltype(instanced)::value) {
        primPool_ ? withHitTest(layout, instanced, Yes{}) : withHitTest(layout, instanced, No{});
      } else {
        withHitTest(layout, instanced, No{});
      }
    });
  }

  // Blocks of 128 threads every traversal kernel keeps per SM, which caps it at 64 registers
  // (it would take 70-114). On an H200 (benchmarks/RESULTS.md, 2026-11-26): flat scenes 0-4%
  // faster per render in the per-ray walks and 9% in the pooled one; with hit tests 10-21%;
  // the instanced bunny field 16% (wide) and 26% (binary).
  static constexpr int kTraversalMinBlocks = 8;

  template <BvhLayout L, bool kInstanced, bool kHitTest, bool kPooled>
  void IntersectLayout(const uint32_t* queue, uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    SortKeyOutput keys = shade_.KeyOutput(sortMode_);
    Counter* counters = counters_.Data();
    backend_.template ParallelFor<kTraversalMinBlocks>(Stage::kIntersect, n, [=] PT_HD(uint32_t i) {
      IntersectPath<L, kInstanced, kHitTest, kPooled>(scene, ps, queue[i], i, keys, counters);
    });
  }

  // Medium (scenes with media only): delta tracking along each traced segment; scattering
  // events are shaded there (src/integrator/stages/medium.h).
  void SampleMedia(const WaveInfo& wave, const uint32_t* queue, uint32_t n) {
    media_.Sample(sceneBuffers_.view, params_, wave, pathState_, queue, n, counters_.Data());
  }

  // Shade: emission, next-event estimation (queues shadow rays), BSDF sampling, roulette;
  // in the variant compiled for the scene's effects (with or without environment-map code),
  // in the order --sort asks for (media scenes: their own variants, in queue order).
  void Shade(const WaveInfo& wave, const uint32_t* queue, uint32_t n) {
    if (media_.Active()) {
      media_.Shade(featureClass_, envMap_, sceneBuffers_.view, params_, wave, pathState_, queue, n);
      return;
    }
    typename ShadeLauncher<Backend>::Inputs in{sceneBuffers_.view, params_, pathState_};
    stats_.pathsOrdered +=
        shade_.Shade(sortMode_, featureClass_, envMap_, FlatShading(), wave, in, queue, n);
  }

  // No vertex normals and no light tree: the shade variants without their code.
  bool FlatShading() const {
    return sceneBuffers_.view.triangleNormals == nullptr && !UsesLightTree(sceneBuffers_.view);
  }

  // Shadow: any-hit test for each queued shadow ray (media scenes: with transmittance).
  void TraceShadowRays(const WaveInfo& wave, const uint32_t* queue, uint32_t n) {
    if (media_.Active()) {
      media_.TraceShadows(sceneBuffers_.view, wave, pathState_, queue, n, counters_.Data());
      return;
    }
    ForTraversal([&](auto layout, auto instanced, auto hitTest, auto pooled) {
      ShadowLayout<decltype(layout)::value, decltype(instanced)::value,
                   decltype(hitTest)::value, decltype(pooled)::value>(queue, n);
    });
  }

  template <BvhLayout L, bool kInstanced, bool kHitTest, bool kPooled>
  void ShadowLayout(const uint32_t* queue, uint32_t n) {
    PathState ps = pathState_;
    SceneView scene = sceneBuffers_.view;
    Counter* counters = counters_.Data();
    backend_.template ParallelFor<kTraversalMinBlocks>(Stage::kShadow, n, [=] PT_HD(uint32_t i) {
      TraceShadowRay<L, kInstanced, kHitTest, kPooled>(scene, ps, queue[i], counters);
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
    float clamp = params_.clampLuminance;
    if (film.evenSum) {
      backend_.ParallelFor(Stage::kAccumulate, wave.pixelCount, [=] PT_HD(uint32_t i) {
        AccumulatePixel<true>(wave, ps, film, i, counters, clamp);
      });
    } else {
      backend_.ParallelFor(Stage::kAccumulate, wave.pixelCount, [=] PT_HD(uint32_t i) {
        AccumulatePixel<false>(wave, ps, film, i, counters, clamp);
      });
    }
  }

  // The film as an image: mean and per-channel sample variance per pixel, resolved on the
  // backend (ResolveFilmImage's values for the saved film).
  FilmImage ResolveFilm() {
    EnsureAllocated();
    return resolved_.Resolve(backend_, film_, filmArrays_, plan_.cropWidth, plan_.cropHeight);
  }

  FilmState SaveFilm() {
    FilmState f;
    SaveFilmInto(f);
    return f;
  }
  // Into f's own arrays (a film of the same size saves with no fresh pages to fault in).
  void SaveFilmInto(FilmState& f) {
    EnsureAllocated();
    filmArrays_.SaveInto(f, plan_.cropWidth, plan_.cropHeight);
  }
  // A copy of the film on the backend (a stage over the pixels, waited for), which
  // SaveSnapshotInto saves, possibly on another thread while this one clears the film and
  // renders on. The next SnapshotFilm must wait until that save has returned.
  void SnapshotFilm();
  void SaveSnapshotInto(FilmState& f) {
    if (snapshot_.Pixels() == 0) throw std::logic_error("SaveSnapshotInto before SnapshotFilm");
    snapshot_.SaveInto(f, plan_.cropWidth, plan_.cropHeight);
  }
  void LoadFilm(const FilmState& film);
  void ResetFilm();
  RenderStats Stats();

  void SetCamera(const Camera& camera) {
    EnsureAllocated();
    sceneBuffers_.view.camera = camera;
  }
  void ApplyOptions(const RenderOptions& options);
  void ApplySortOptions();
  void ApplyLightSampler();
  void SceneChanged();
  void TopLevelChanged();
  void MaterialsChanged();

 private:
  using Clock = std::chrono::steady_clock;
  static double Ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  }

  // Runs a render step with the buffers allocated, its wall time added to the statistics.
  template <typename F>
  uint64_t Timed(F step) {
    EnsureAllocated();
    stopped_ = false;
    auto start = Clock::now();
    uint64_t done = step();
    backend_.Synchronize();
    stats_.renderMs += Ms(start, Clock::now());
    return done;
  }
  uint32_t PathCapacity() const { return uint32_t(queue_.Size()); }
  void EnsureAllocated() {
    if (!allocated_) Allocate();
  }
  void Allocate();
  void WarmUp();
  void AllocatePaths(size_t n);
  void AllocateFilm(size_t pixels);
  bool StopRequested();
  void AfterWave(uint64_t done, uint64_t total);
  RenderResult Finish(uint64_t samplesDone);

  Backend& backend_;
  const Scene& scene_;
  RenderOptions options_;
  RenderCallbacks callbacks_;
  bool compact_ = true;
  bool rayOrder_ = false;  // --ray-order, auto resolved
  bool primPool_ = false;  // --prim-pool, auto resolved (wide layout, flat scene, GPU)
  SortMode sortMode_ = SortMode::kOff;  // auto resolved
  bool allocated_ = false, filmFresh_ = true;
  WavePlan plan_;
  IntegratorParams params_{};
  SceneBuffers<Backend> sceneBuffers_;

  Buffer<vec3> rayOrigin_, rayDir_, throughput_, radiance_, shadowOrigin_, shadowDir_,
      shadowRadiance_;
  Buffer<float> prevPdf_, shadowTMax_;
  Buffer<uint32_t> flags_, queue_;
  Buffer<uint32_t> rayKeys_, rayKeysOut_, rayQueue_;  // --ray-order's keys and ordered queue
  ShadeLauncher<Backend> shade_{backend_};
  MediaPass<Backend> media_{backend_};  // participating media (inactive without them)
  Buffer<PathHit> hit_;
  Buffer<uint32_t> hitInstance_;
  Buffer<uint32_t> prevNormal_;  // the light BVH sampler's receiver normals
  Buffer<vec3> featureAlbedo_, featureNormal_, featureEmission_;
  Buffer<float> featureDepth_;
  PathState pathState_{};
  FilmBuffers<Backend> filmArrays_, snapshot_;  // the film; SnapshotFilm's copy
  Buffer<uint32_t> activePixels_, resumePixels_;
  ResolvedImage<Backend> resolved_;       // ResolveFilm's planes, kept
  FilmView film_{};
  AdaptiveSettings adaptive_;
  FeatureClass featureClass_ = FeatureClass::kGeneral;
  bool envMap_ = false;  // the scene has an environment map
  LightSampler lightSampler_ = LightSampler::kPower;  // auto resolved
  // The hit-test traversal variants: some material asks for a hit test (alpha, back-face
  // culling), or --tri-test box-clamped (whose raise only they compile).
  bool hitTests_ = true;
  bool stopped_ = false;
  Buffer<Counter> counters_;

  RenderStats stats_;
  Clock::time_point renderStart_, lastPreview_;  // the first render step's start
  double lastRelMseLog_ = -1.0;
};

}  // namespace pt

#include "src/integrator/wavefront_impl.h"
