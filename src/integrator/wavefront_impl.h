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
  return p;
}

template <typename Backend>
void WavefrontIntegrator<Backend>::Allocate() {
  params_ = MakeParams(scene_.desc.render, options_);
  featureClass_ = options_.specialize ? ChooseFeatureClass(AnalyzeEffects(scene_))
                                      : FeatureClass::kGeneral;
  stats_.specialization = FeatureClassName(featureClass_);
  adaptive_ = scene_.desc.render.adaptive;
  if (options_.adaptive != Toggle::kAuto) adaptive_.enabled = options_.adaptive == Toggle::kOn;
  UploadScene(scene_, sceneBuffers_);
  sceneBuffers_.view.triangleTest = options_.triangleTest == TriangleTest::kMollerTrumbore;
  // Adaptive waves over fewer pixels pack more samples per wave: up to the path budget.
  size_t capacity = plan_.pathCapacity;
  if (adaptive_.enabled)
    capacity = std::min<size_t>(std::max<size_t>(plan_.maxPaths, 1),
                                size_t(plan_.cropPixels) * plan_.spp);
  AllocatePaths(capacity);
  AllocateFilm(plan_.cropPixels);
  counters_.Resize(kCounterCount);
  counters_.Zero();
  stats_.compactUsed = compact_;
  stats_.sortUsed = sort_;
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
  sortKeys_.Resize(n);
  hit_.Resize(n);
  // Feature buffers exist only when asked for: a render without them pays nothing.
  size_t features = params_.featureBuffers ? n : 0;
  featureAlbedo_.Resize(features);
  featureNormal_.Resize(features);
  featureDepth_.Resize(features);
  pathState_ = PathState{rayOrigin_.Data(),      rayDir_.Data(),        throughput_.Data(),
                         radiance_.Data(),       prevPdf_.Data(),       flags_.Data(),
                         hit_.Data(),            shadowOrigin_.Data(),  shadowDir_.Data(),
                         shadowTMax_.Data(),     shadowRadiance_.Data(), featureAlbedo_.Data(),
                         featureNormal_.Data(),  featureDepth_.Data()};
  stats_.pathsInFlight = n;
  stats_.pathStateBytesPerPath = kPathStateBytes + backend_.SortScratchBytesPerPath(sort_) +
                                 (params_.featureBuffers ? kFeatureBytes : 0);
}

template <typename Backend>
void WavefrontIntegrator<Backend>::AllocateFilm(size_t pixels) {
  bool dbl = options_.filmDouble;
  filmMean_.Resize(dbl ? 0 : pixels);
  filmM2_.Resize(dbl ? 0 : pixels);
  filmMeanDouble_.Resize(dbl ? pixels : 0);
  filmM2Double_.Resize(dbl ? pixels : 0);
  size_t features = params_.featureBuffers ? pixels : 0;
  filmAlbedo_.Resize(features);
  filmNormal_.Resize(features);
  filmDepth_.Resize(features);
  filmLumMean_.Resize(pixels);
  filmLumM2_.Resize(pixels);
  filmCount_.Resize(pixels);
  activePixels_.Resize(adaptive_.enabled ? pixels : 0);
  for (auto* b : {&filmMean_, &filmM2_, &filmAlbedo_, &filmNormal_}) b->Zero();
  filmMeanDouble_.Zero();
  filmM2Double_.Zero();
  for (auto* b : {&filmLumMean_, &filmLumM2_, &filmDepth_}) b->Zero();
  filmCount_.Zero();
  film_ = FilmView{filmMean_.Data(),    filmM2_.Data(),     filmMeanDouble_.Data(),
                   filmM2Double_.Data(), filmLumMean_.Data(), filmLumM2_.Data(),
                   filmCount_.Data(),   filmAlbedo_.Data(), filmNormal_.Data(),
                   filmDepth_.Data()};
  if (adaptive_.enabled) ResetActivePixels();
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
RenderResult WavefrontIntegrator<Backend>::Finish(uint64_t samplesDone) {
  std::vector<Counter> counters;
  counters_.Download(counters);
  stats_.shadowRays = counters[kCounterShadowRays];
  stats_.nodesVisited = counters[kCounterNodesVisited];
  stats_.primsTested = counters[kCounterPrimsTested];
  stats_.traversals = counters[kCounterTraversals];
  stats_.nonfiniteSamples = counters[kCounterNonfinite];
  stats_.samples = samplesDone;
  stats_.stages = backend_.Times();
  stats_.backend = backend_.Name();
  stats_.device = backend_.DeviceName();
  stats_.threads = backend_.ThreadCount();
  stats_.peakDeviceBytes = backend_.PeakBytes();

  RenderResult result;
  result.image = ResolveFilm();
  uint64_t pixels = std::max<uint64_t>(1, plan_.cropPixels);
  stats_.sppMean = double(samplesDone) / double(pixels);
  result.stats = stats_;
  return result;
}

}  // namespace pt
