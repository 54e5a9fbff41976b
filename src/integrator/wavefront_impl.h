// The host-side bookkeeping of WavefrontIntegrator: allocation, stopping, previews, stats.
#pragma once

namespace pt {

template <typename Backend>
void WavefrontIntegrator<Backend>::Allocate() {
  const RenderSettings& r = scene_.desc.render;
  params_.maxDepth = r.maxDepth;
  params_.rrDepth = r.russianRouletteDepth;
  params_.kind = options_.integrator == IntegratorMode::kBsdf  ? IntegratorKind::kBsdf
                 : options_.integrator == IntegratorMode::kNee ? IntegratorKind::kNee
                                                               : IntegratorKind::kMis;
  UploadScene(scene_, sceneBuffers_);

  size_t n = plan_.pathCapacity;
  for (Buffer<vec3>* b : {&rayOrigin_, &rayDir_, &throughput_, &radiance_, &shadowOrigin_,
                          &shadowDir_, &shadowRadiance_})
    b->Resize(n);
  prevPdf_.Resize(n);
  shadowTMax_.Resize(n);
  flags_.Resize(n);
  queue_.Resize(n);
  sortKeys_.Resize(n);
  hit_.Resize(n);
  pathState_ = PathState{rayOrigin_.Data(), rayDir_.Data(),      throughput_.Data(),
                         radiance_.Data(),  prevPdf_.Data(),     flags_.Data(),
                         hit_.Data(),       shadowOrigin_.Data(), shadowDir_.Data(),
                         shadowTMax_.Data(), shadowRadiance_.Data()};

  size_t pixels = plan_.cropPixels;
  filmSum_.Resize(pixels);
  filmSumSquares_.Resize(pixels);
  filmCount_.Resize(pixels);
  filmSum_.Zero();
  filmSumSquares_.Zero();
  filmCount_.Zero();
  film_ = FilmView{filmSum_.Data(), filmSumSquares_.Data(), filmCount_.Data()};
  counters_.Resize(kCounterCount);
  counters_.Zero();

  stats_.pathsInFlight = n;
  stats_.pathStateBytesPerPath = kPathStateBytes + backend_.SortScratchBytesPerPath(sort_);
  stats_.compactUsed = compact_;
  stats_.sortUsed = sort_;
}

template <typename Backend>
bool WavefrontIntegrator<Backend>::StopRequested() {
  if (callbacks_.shouldStop && callbacks_.shouldStop()) {
    stats_.interrupted = true;
    return true;
  }
  double limit = options_.timeLimitSeconds;
  return limit > 0.0 && Ms(renderStart_, Clock::now()) >= limit * 1000.0;
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
