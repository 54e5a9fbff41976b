// The host-side bookkeeping of WavefrontIntegrator: allocation, stopping, previews, stats.
#pragma once

namespace pt {

// What the options ask of the stages.
inline IntegratorParams MakeParams(const RenderSettings& r, const RenderOptions& o) {
  IntegratorParams p{};
  p.maxDepth = r.maxDepth;
  p.rrDepth = r.russianRouletteDepth;
  p.kind = o.integrator == IntegratorMode::kBsdf  ? IntegratorKind::kBsdf
           : o.integrator == IntegratorMode::kNee ? IntegratorKind::kNee
                                                  : IntegratorKind::kMis;
  p.minBounces = o.lightPaths == LightPaths::kIndirect ? 2u : 0u;
  p.maxBounces = o.lightPaths == LightPaths::kDirect ? 1u : 0xffffffffu;
  // Direct light needs no path past its first bounce.
  if (o.lightPaths == LightPaths::kDirect) p.maxDepth = std::min(p.maxDepth, 1);
  p.rayOffsetEpsilon = o.rayOffsetEpsilon;
  p.featureBuffers = o.featureBuffers ? 1u : 0u;
  p.clampLuminance = o.clampLuminance;
  return p;
}

// What the options ask of the stages and the queue. Structural options (film precision,
// feature buffers, crop, paths in flight, adaptive) are read once, by Allocate.
template <typename Backend>
void WavefrontIntegrator<Backend>::ApplyOptions(const RenderOptions& o) {
  options_.compact = o.compact;
  options_.sort = o.sort;
  options_.sortMethod = o.sortMethod;
  options_.rayOrder = o.rayOrder;
  options_.primPool = o.primPool;
  options_.warmUp = o.warmUp;
  options_.integrator = o.integrator;
  options_.lightPaths = o.lightPaths;
  options_.specialize = o.specialize;
  options_.rayOffsetEpsilon = o.rayOffsetEpsilon;
  options_.triangleTest = o.triangleTest;
  options_.envSampling = o.envSampling;
  options_.timeLimitSeconds = o.timeLimitSeconds;
  options_.previewEverySeconds = o.previewEverySeconds;
  options_.clampLuminance = o.clampLuminance;
  options_.lightSampler = o.lightSampler;
  ApplyLightSampler();
  options_.transmittance = o.transmittance;
  // Every wave is cut from the plan's base, so its paths' keys draw from this sampler.
  options_.sampler = o.sampler;
  plan_.base.sampler = o.sampler.value_or(scene_.desc.render.sampler);
  if (plan_.base.sampler == SamplerKind::kSobol && options_.halfFilms)
    plan_.base.sampler = SamplerKind::kSobolHalves;  // two replicates, one per half film
  stats_.sampler = SamplerKindName(plan_.base.sampler);
  FlagChoice flags = ChooseFlags(options_);
  compact_ = flags.compact;
  stats_.compactUsed = compact_;
  // Placed primitives: a field of 10^4 instanced bunnies (69k stored triangles) gains too.
  rayOrder_ = ChooseRayOrder(options_.rayOrder, Backend::kLockstepLanes,
                             std::max<uint64_t>(scene_.prims.size(), scene_.PlacedTriangleCount()));
  stats_.rayOrderUsed = rayOrder_;
  primPool_ = ChoosePrimPool(options_.primPool, Backend::kLockstepLanes,
                             scene_.bvhLayout == BvhLayout::kWide && scene_.instances.empty(),
                             scene_.prims.size());
  stats_.primPoolUsed = primPool_;
  params_ = MakeParams(scene_.desc.render, options_);
  uint32_t effects = AnalyzeEffects(scene_);
  featureClass_ =
      options_.specialize ? ChooseFeatureClass(effects) : UnspecializedFeatureClass(effects);
  envMap_ = (effects & kEffectEnvironmentMap) != 0;
  // --tri-test box-clamped's raise is compiled into the hit-test variants only (shapes.h).
  hitTests_ = (effects & (kEffectAlpha | kEffectBackfaceCulling)) != 0 ||
              options_.triangleTest == TriangleTest::kBoxClamped;
  media_.SetEstimator(options_.transmittance == TransmittanceMode::kDelta
                          ? TransmittanceEstimator::kDelta
                          : TransmittanceEstimator::kRatio);
  ApplySortOptions();
  static_assert(uint32_t(TriangleTest::kMollerTrumbore) == kTriTestMollerTrumbore &&
                uint32_t(TriangleTest::kBoxClamped) == kTriTestBoxClamped);
  sceneBuffers_.view.triangleTest = uint32_t(options_.triangleTest);
  sceneBuffers_.view.env.uniformSampling = options_.envSampling == EnvSampling::kUniform;
}

// The light sampler auto's rule or the options choose; the BVH's receiver normals per path.
template <typename Backend>
void WavefrontIntegrator<Backend>::ApplyLightSampler() {
  lightSampler_ = ChooseLightSampler(options_.lightSampler, scene_);
  stats_.lightSampler = LightSamplerName(lightSampler_);
  sceneBuffers_.view.lightTree.sampler = uint32_t(lightSampler_);
  if (lightSampler_ == LightSampler::kBvh && prevNormal_.Size() < queue_.Size()) {
    prevNormal_.Resize(queue_.Size());
    pathState_.prevNormal = prevNormal_.Data();
  }
}

// The shading order: auto's choice from the scene's materials, the keys, the ordering buffers.
template <typename Backend>
void WavefrontIntegrator<Backend>::ApplySortOptions() {
  shade_.SetScene(scene_, options_.sortMethod);
  SortChoice choice =
      ChooseSortMode(options_.sort, shade_.Keys(), featureClass_, Backend::kLockstepLanes);
  sortMode_ = choice.mode;
  if (media_.Active() && sortMode_ != SortMode::kOff) {  // media variants shade in queue order
    sortMode_ = SortMode::kOff;
    choice.reason = "media scenes shade in queue order";
  }
  bool ordering = sortMode_ != SortMode::kOff;
  if (ordering && queue_.Size() > 0) shade_.EnsureOrdering(queue_.Size());
  stats_.sortUsed = ordering;
  stats_.sortMode = SortModeName(sortMode_);
  stats_.sortMethod = ordering ? SortMethodName(shade_.Method()) : "";
  stats_.sortReason = choice.reason;
  // The variant that runs, as Shade chooses it (media scenes: their own, never flat).
  const bool flatCopy = !media_.Active() && ShadeLauncher<Backend>::RunsFlatCopy(
                                                sortMode_, featureClass_, envMap_, FlatShading());
  stats_.specialization = std::string(FeatureClassName(featureClass_)) + (flatCopy ? "-flat" : "");
}

// The Scene was edited: its arrays again (a camera set on the session stays), and what the
// options derive from it.
template <typename Backend>
void WavefrontIntegrator<Backend>::SceneChanged() {
  EnsureAllocated();
  UploadSceneArrays(scene_, sceneBuffers_, [](const char*) { return true; });
  media_.SetScene(scene_);
  media_.AllocatePaths(queue_.Size());
  if (scene_.HasInstances() && hitInstance_.Size() < queue_.Size()) {
    hitInstance_.Resize(queue_.Size());
    pathState_.hitInstance = hitInstance_.Data();
  }
  ApplyOptions(options_);
}

// Only materials were edited (and BuildLightTable ran): the arrays they reach, not the
// geometry; the stage variant follows the materials' effects.
template <typename Backend>
void WavefrontIntegrator<Backend>::MaterialsChanged() {
  EnsureAllocated();
  UploadSceneArrays(scene_, sceneBuffers_, IsAppearanceArray);
  ApplyOptions(options_);
}

// Instances were moved and RebuildTopLevel ran: only the top-level arrays travel again.
template <typename Backend>
void WavefrontIntegrator<Backend>::TopLevelChanged() {
  EnsureAllocated();
  UploadTopLevel(scene_, sceneBuffers_);
}

template <typename Backend>
void WavefrontIntegrator<Backend>::Allocate() {
  auto t0 = Clock::now();
  allocated_ = true;
  renderStart_ = lastPreview_ = Clock::now();
  adaptive_ = scene_.desc.render.adaptive;
  if (options_.adaptive != Toggle::kAuto) adaptive_.enabled = options_.adaptive == Toggle::kOn;
  UploadScene(scene_, sceneBuffers_);
  media_.SetScene(scene_);
  ApplyOptions(options_);
  // Adaptive waves over fewer pixels pack more samples per wave: up to the path budget.
  size_t capacity = plan_.pathCapacity;
  if (adaptive_.enabled)
    capacity = std::min<size_t>(std::max<size_t>(plan_.maxPaths, 1),
                                size_t(plan_.cropPixels) * plan_.spp);
  AllocatePaths(capacity);
  AllocateFilm(plan_.cropPixels);
  counters_.Resize(kCounterCount);
  counters_.Zero();
  stats_.uploadMs = Ms(t0, Clock::now());
  WarmUp();
  renderStart_ = lastPreview_ = Clock::now();
}

// A backend that loads each kernel at its first launch (CUDA's default, lazy module loading)
// would put that loading into the first wave's stage times. A short wave from the image's
// middle rows, traced through every bounce and then discarded (film, counters, stage times and
// ray counts reset), loads the kernels the scene runs before the render's clock starts (2-6 ms
// on an H100); loading every kernel of every module at start-up instead
// (CUDA_MODULE_LOADING=EAGER) made runs 30-80 ms slower to an image (benchmarks/RESULTS.md).
// Kernels of paths the short wave did not take still load when first launched. The random
// streams are keyed per pixel and sample, so the render's samples are those it would have
// drawn without the warm-up.
template <typename Backend>
void WavefrontIntegrator<Backend>::WarmUp() {
  const bool wanted = options_.warmUp == Toggle::kAuto ? backend_.LoadsKernelsOnFirstUse()
                                                        : options_.warmUp == Toggle::kOn;
  if (!wanted) return;
  constexpr uint32_t kWarmUpPaths = 4096;
  auto t0 = Clock::now();
  WaveInfo wave = plan_.base;
  wave.pixelList = nullptr;
  wave.pixelCount = std::min({kWarmUpPaths, plan_.cropPixels, PathCapacity()});
  if (wave.pixelCount == 0) return;
  wave.pixelStart = (plan_.cropPixels - wave.pixelCount) / 2;
  wave.sampleStart = 0;
  wave.samplesInWave = 1;
  const RenderStats kept = stats_;
  RunWave(wave);
  ResetFilm();
  counters_.Zero();
  backend_.ResetTimes();
  stats_ = kept;
  stats_.warmedUp = true;
  stats_.warmUpMs = Ms(t0, Clock::now());
}

template <typename Backend>
void WavefrontIntegrator<Backend>::AllocatePaths(size_t n) {
  for (Buffer<vec3>* b : {&rayOrigin_, &rayDir_, &throughput_, &radiance_, &shadowOrigin_,
                          &shadowDir_, &shadowRadiance_})
    b->Resize(n);
  prevPdf_.Resize(n);
  shadowTMax_.Resize(n);
  flags_.Resize(n);
  queue_.Resize(n);
  if (sortMode_ != SortMode::kOff) shade_.EnsureOrdering(n);
  hit_.Resize(n);
  hitInstance_.Resize(scene_.HasInstances() ? n : 0);
  media_.AllocatePaths(n);
  // Feature buffers exist only when asked for: a render without them pays nothing.
  size_t features = params_.featureBuffers ? n : 0;
  featureAlbedo_.Resize(features);
  featureNormal_.Resize(features);
  featureDepth_.Resize(features);
  featureEmission_.Resize(features);
  pathState_ = PathState{rayOrigin_.Data(),      rayDir_.Data(),        throughput_.Data(),
                         radiance_.Data(),       prevPdf_.Data(),       flags_.Data(),
                         hit_.Data(),            shadowOrigin_.Data(),  shadowDir_.Data(),
                         shadowTMax_.Data(),     shadowRadiance_.Data(), featureAlbedo_.Data(),
                         featureNormal_.Data(),  featureDepth_.Data(),  featureEmission_.Data(),
                         hitInstance_.Data()};
  prevNormal_.Resize(lightSampler_ == LightSampler::kBvh ? n : 0);
  pathState_.prevNormal = prevNormal_.Data();
  stats_.pathsInFlight = n;
  stats_.pathStateBytesPerPath = kPathStateBytes + shade_.BytesPerPath() +
                                 (rayOrder_ ? 3 * sizeof(uint32_t) : 0) +
                                 (params_.featureBuffers ? kFeatureBytes : 0) +
                                 (scene_.HasInstances() ? kInstanceHitBytes : 0) +
                                 (lightSampler_ == LightSampler::kBvh ? kReceiverBytes : 0) +
                                 media_.BytesPerPath();
}

template <typename Backend>
void WavefrontIntegrator<Backend>::AllocateFilm(size_t pixels) {
  filmArrays_.Allocate(pixels, options_.filmDouble, params_.featureBuffers != 0,
                       options_.halfFilms);
  activePixels_.Resize(adaptive_.enabled ? pixels : 0);
  film_ = filmArrays_.View();
  ResetFilm();
}

template <typename Backend>
void WavefrontIntegrator<Backend>::SnapshotFilm() {
  EnsureAllocated();
  if (snapshot_.Pixels() != filmArrays_.Pixels())
    snapshot_.Allocate(plan_.cropPixels, options_.filmDouble, params_.featureBuffers != 0,
                       options_.halfFilms);
  FilmView from = film_, to = snapshot_.View();
  backend_.ParallelFor(Stage::kAccumulate, plan_.cropPixels,
                       [=] PT_HD(uint32_t i) { CopyFilmPixel(to, from, i); });
  backend_.Synchronize();
}

template <typename Backend>
void WavefrontIntegrator<Backend>::ResetFilm() {
  // One stage over the pixels instead of a fill per array: on the GPU one kernel on the
  // render's stream (separate fills each waited behind the other lane's kernels under MPI),
  // on the CPU every thread. Waited for, since downloads and uploads use another stream.
  EnsureAllocated();
  FilmView film = film_;
  backend_.ParallelFor(Stage::kAccumulate, plan_.cropPixels,
                       [=] PT_HD(uint32_t i) { ClearFilmPixel(film, i); });
  backend_.Synchronize();
  filmFresh_ = true;
  if (adaptive_.enabled) ResetActivePixels();
}

template <typename Backend>
void WavefrontIntegrator<Backend>::LoadFilm(const FilmState& f) {
  EnsureAllocated();
  filmArrays_.LoadFrom(f, plan_.cropWidth, plan_.cropHeight);
  filmFresh_ = false;
}

template <typename Backend>
bool WavefrontIntegrator<Backend>::StopRequested() {
  if (callbacks_.shouldStop && callbacks_.shouldStop()) {
    stats_.interrupted = true;
    return stopped_ = true;
  }
  double limit = options_.timeLimitSeconds;
  if (limit > 0.0 && Ms(renderStart_, Clock::now()) >= limit * 1000.0) stopped_ = true;
  return stopped_;
}

template <typename Backend>
void WavefrontIntegrator<Backend>::AfterWave(uint64_t done, uint64_t total) {
  if (callbacks_.onProgress) callbacks_.onProgress(done, total);
  auto now = Clock::now();
  double seconds = Ms(renderStart_, now) / 1000.0;
  // relMSE against a reference, logged at most 20 times a second.
  if (options_.reference && (seconds - lastRelMseLog_ >= 0.05 || done == total)) {
    FilmImage img = ResolveFilm();
    stats_.referenceRelMse.emplace_back(seconds, RelMse(img.rgb, *options_.reference));
    lastRelMseLog_ = seconds;
  }
  if (options_.previewEverySeconds > 0.0 && callbacks_.onPreview &&
      Ms(lastPreview_, now) >= options_.previewEverySeconds * 1000.0) {
    callbacks_.onPreview(ResolveFilm());
    lastPreview_ = Clock::now();
  }
}

template <typename Backend>
RenderStats WavefrontIntegrator<Backend>::Stats() {
  EnsureAllocated();
  std::vector<Counter> counters;
  counters_.Download(counters);
  stats_.shadowRays = counters[kCounterShadowRays];
  stats_.nodesVisited = counters[kCounterNodesVisited];
  stats_.primsTested = counters[kCounterPrimsTested];
  stats_.traversals = counters[kCounterTraversals];
  stats_.nonfiniteSamples = counters[kCounterNonfinite];
  stats_.stages = backend_.Times();
  stats_.backend = backend_.Name();
  stats_.device = backend_.DeviceName();
  stats_.threads = backend_.ThreadCount();
  stats_.peakDeviceBytes = backend_.PeakBytes();
  return stats_;
}

template <typename Backend>
RenderResult WavefrontIntegrator<Backend>::Finish(uint64_t samplesDone) {
  RenderResult result;
  result.stats = Stats();
  result.stats.samples = samplesDone;
  result.image = ResolveFilm();
  // Samples per pixel in the film (a resumed render counts what it continued from).
  uint64_t filmSamples = 0;
  for (uint32_t c : result.image.samples) filmSamples += c;
  result.stats.sppMean = double(filmSamples) / double(std::max<uint64_t>(1, plan_.cropPixels));
  return result;
}

}  // namespace pt
