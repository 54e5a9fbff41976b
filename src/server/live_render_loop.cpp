// LiveRender's threads: the render thread (edits applied between waves, coarse frames while
// edits keep coming, full-resolution passes) and the encoder (film image -> JPEG frame).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/lights/light_table.h"
#include "src/scene/instances.h"
#include "src/server/live_render.h"

namespace pt {

using LoopClock = std::chrono::steady_clock;

namespace {

double MsFrom(LoopClock::time_point a, LoopClock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// A pass aims at this much render time, so frames keep coming while the film converges.
constexpr double kPassTargetMs = 60.0;
constexpr uint32_t kMaxSamplesPerPass = 16;
constexpr int kMaxCoarseDivisor = 16;

// The first width x height pixels of a film image, as an image of that size.
std::shared_ptr<const FilmImage> CoarseImage(const FilmImage& film, int width, int height) {
  auto image = std::make_shared<FilmImage>();
  image->width = width;
  image->height = height;
  size_t n = size_t(width) * size_t(height);
  image->rgb.assign(film.rgb.begin(), film.rgb.begin() + std::ptrdiff_t(3 * n));
  return image;
}

}  // namespace

void LiveRender::RenderLoop() {
  while (!stop_) {
    try {
      bool restarted = ApplyEdits();
      // Only when a full-resolution sample is slow, or newer edits keep dropping it: then a
      // coarse frame shows the edit soon.
      bool slow = msPerSpp_ > 1.5 * settings_.coarseFrameMs || editsOutpaceSamples_;
      if (restarted && settings_.coarseFrameMs > 0.0 && slow) {
        RenderCoarseFrame();
        continue;
      }
      if (spp_ >= targetSpp_) {
        std::unique_lock<std::mutex> lock(wakeMutex_);
        wake_.wait(lock, [&] { return stop_ || wakeCalls_; });
        continue;
      }
      RenderPass();
    } catch (const std::exception& e) {  // never let one edit end the preview
      std::fprintf(stderr, "pathtracer: serve: %s\n", e.what());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

bool LiveRender::ApplyEdits() {
  std::unique_ptr<Pending> p;
  uint64_t generation;
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    std::lock_guard<std::mutex> wakeLock(wakeMutex_);
    wakeCalls_ = false;
    editsWaiting_ = false;
    p = std::exchange(pending_, std::make_unique<Pending>());
    generation = requestedGeneration_;
  }
  if (p->spp) {
    targetSpp_ = *p->spp;
    // At or below the samples rendered: the film as it stands is the render's last frame, and
    // its statistics say why it ends (after any frame still being encoded).
    if (!p->restart && spp_ > 0 && targetSpp_ <= spp_) {
      Publish(StatsJson(session_->Stats(), lastPassMs_, lastPassSpp_), false, nullptr);
    }
  }
  if (!p->restart) return false;
  {
    std::unique_lock<std::shared_mutex> lock(sceneMutex_);
    if (p->maxDepth) scene_.desc.render.maxDepth = *p->maxDepth;
    if (p->options) options_ = *p->options;
    ApplySceneEdits(*p);
    if (p->options || p->maxDepth) session_->SetOptions(options_);
    if (p->camera) {
      camera_ = MakeCamera(*p->camera, width_, height_, scene_.desc.render.spp);
      scene_.desc.camera = *p->camera;
      session_->SetCamera(camera_);
    }
    session_->ResetFilm();
  }
  spp_ = 0;
  generation_ = generation;
  firstFrameOfGeneration_ = firstFullFrame_ = true;
  filmHoldsCoarse_ = false;
  editReceived_ = p->firstReceived;
  generationStart_ = lastPassEnd_ = session_->Stats();
  return true;
}

// Moves, materials and lighting, by the cheapest update that covers them: instance moves
// alone re-place through the top level, any other move rebuilds the scene.
void LiveRender::ApplySceneEdits(const Pending& p) {
  auto t0 = LoopClock::now();
  for (const auto& [index, toWorld] : p.placements) UpdateInstanceTransform(scene_, index, toWorld);
  for (const auto& [index, moved] : p.moves) objects_.Place(index, moved, scene_.desc);
  for (const auto& [index, material] : p.materials) scene_.desc.materials[index] = material;
  if (p.lighting) ApplyLighting(*p.lighting);
  if (!p.moves.empty()) {
    scene_ = BuildScene(std::move(scene_.desc), scene_.bvhOptions);
    session_->SceneChanged();
    ++sceneRebuilds_;
  } else {
    if (!p.placements.empty()) RebuildTopLevel(scene_);
    // After the top level (its bounds); the environment's tables are the light table's.
    if (!p.materials.empty() || p.lighting) BuildLightTable(scene_);
    if (!p.placements.empty()) {
      session_->TopLevelChanged();
      ++topLevelRebuilds_;
    }
    // A new map (or none) changes arrays and the stage variant beyond the materials'.
    if (p.lighting) session_->SceneChanged();
    else if (!p.materials.empty()) session_->MaterialsChanged();
  }
  if (!p.moves.empty() || !p.placements.empty()) lastRebuildMs_ = MsFrom(t0, LoopClock::now());
}

// The lighting at infinity of `lit` (a scene of the document's lighting alone) replaces the
// scene's: environment, background, and the sky's sun among the directional lights.
void LiveRender::ApplyLighting(const SceneDesc& lit) {
  SceneDesc& d = scene_.desc;
  d.environment = lit.environment;
  d.background = lit.background;
  auto& lights = d.directionalLights;
  lights.erase(std::remove_if(lights.begin(), lights.end(),
                              [](const DirectionalLightDesc& l) { return l.partOfEnvironment; }),
               lights.end());
  for (const DirectionalLightDesc& l : lit.directionalLights) {
    if (l.partOfEnvironment) lights.push_back(l);
  }
}

// A frame at 1/k of the resolution, k chosen so that it takes about coarseFrameMs; its waves
// are not dropped by newer edits (it is what shows them while they keep coming).
void LiveRender::RenderCoarseFrame() {
  int k = int(std::ceil(std::sqrt(msPerSpp_ / settings_.coarseFrameMs)));
  k = std::clamp(k, 2, kMaxCoarseDivisor);
  int w = (width_ + k - 1) / k, h = (height_ + k - 1) / k;
  Camera coarse = camera_;
  coarse.pixelSpread *= float(height_) / float(h);  // texture footprints of the bigger pixels
  uint64_t done;
  coarseUnderWay_ = true;
  filmHoldsCoarse_ = true;
  {
    std::shared_lock<std::shared_mutex> lock(sceneMutex_);
    session_->SetCamera(coarse);
    done = session_->RenderCoarse(uint32_t(w), uint32_t(h), 0, 1);
    session_->SetCamera(camera_);
  }
  coarseUnderWay_ = false;
  std::shared_ptr<const FilmImage> image;
  if (done == uint64_t(w) * uint64_t(h)) image = CoarseImage(session_->Image(), w, h);
  session_->ResetFilm();
  filmHoldsCoarse_ = false;
  RenderStats now = session_->Stats();
  if (image) {
    Json stats = Json::parse(StatsJson(now, now.renderMs - lastPassEnd_.renderMs, 1));
    stats["coarse"] = Json{{"width", w}, {"height", h}, {"divisor", k}};
    Publish(stats.dump(), true, image);
  }
  generationStart_ = lastPassEnd_ = now;  // the generation's rates count full samples only
}

void LiveRender::RenderPass() {
  RenderStats before = lastPassEnd_;
  uint64_t passSamples = uint64_t(width_) * height_;
  uint32_t count = msPerSpp_ > 0.0 ? uint32_t(std::clamp(kPassTargetMs / msPerSpp_, 1.0,
                                                        double(kMaxSamplesPerPass)))
                                   : 1u;
  // An edit's first sample alone, then passes that double: the edit shows after one sample
  // (a pass of kPassTargetMs would be dropped by the next move of a drag, and show nothing).
  count = std::min({count, std::max(spp_.load(), 1u), targetSpp_ - spp_});
  uint64_t done;
  {
    std::shared_lock<std::shared_mutex> lock(sceneMutex_);
    done = session_->RenderRange(spp_, spp_ + count);
  }
  if (done < passSamples * count) {  // an edit stopped it: the film starts over
    if (spp_ == 0) editsOutpaceSamples_ = true;
    return;
  }
  editsOutpaceSamples_ = false;
  spp_ += count;
  RenderStats now = session_->Stats();
  lastPassMs_ = now.renderMs - before.renderMs;
  lastPassSpp_ = count;
  msPerSpp_ = lastPassMs_ / count;
  std::string stats = StatsJson(now, lastPassMs_, count);
  lastPassEnd_ = now;
  Publish(stats, false, nullptr);
}

void LiveRender::Publish(const std::string& statsJson, bool coarse,
                         std::shared_ptr<const FilmImage> image) {
  auto now = LoopClock::now();
  bool due = coarse || firstFrameOfGeneration_ || firstFullFrame_ || spp_ >= targetSpp_ ||
             MsFrom(lastPublish_, now) >= 1000.0 / settings_.framesPerSecond;
  if (!due) return;
  if (!image) image = std::make_shared<const FilmImage>(session_->Image());
  lastPublish_ = now;
  Json stats = Json::parse(statsJson);
  bool finished = !coarse && spp_ >= targetSpp_;
  stats["state"] = finished ? "done" : "rendering";
  if (finished && spp_ > targetSpp_) {
    stats["state"] = "stopped";
    stats["message"] = "the target of " + std::to_string(targetSpp_) + " spp is below the " +
                       std::to_string(spp_.load()) + " spp rendered: the render ends at " +
                       std::to_string(spp_.load()) + " spp";
  } else if (finished) {
    stats["message"] = "reached the target of " + std::to_string(targetSpp_) + " spp";
  }
  std::lock_guard<std::mutex> lock(frameMutex_);
  encoding_->image = RenderedImage{std::move(image),
                                   options_.sampler.value_or(SamplerKind::kIndependent)};
  encoding_->generation = generation_;
  encoding_->spp = spp_;
  encoding_->kind = coarse ? "coarse" : "render";
  encoding_->statsJson = stats.dump();
  encoding_->editReceived = firstFrameOfGeneration_ ? editReceived_ : LoopClock::time_point();
  encoding_->waiting = true;
  firstFrameOfGeneration_ = false;
  if (!coarse) firstFullFrame_ = false;
  frameReady_.notify_all();
}

// ---- The encoder thread -----------------------------------------------------------------------

void LiveRender::EncodeAgain() {
  std::lock_guard<std::mutex> lock(frameMutex_);
  if (!frame_ || !shownImage_.film) return;
  encoding_->image = shownImage_;
  encoding_->generation = frame_->generation;
  encoding_->spp = frame_->spp;
  encoding_->kind = "display";
  encoding_->statsJson = frame_->statsJson;
  encoding_->editReceived = LoopClock::time_point();
  encoding_->waiting = true;
  frameReady_.notify_all();
}

void LiveRender::EncodeLoop() {
  uint64_t nextId = 1;
  std::unique_lock<std::mutex> lock(frameMutex_);
  while (!stop_) {
    frameReady_.wait(lock, [&] { return stop_ || encoding_->waiting; });
    if (stop_) break;
    Encoding job = *encoding_;
    encoding_->waiting = false;
    lock.unlock();
    auto frame = std::make_shared<PreviewFrame>();
    frame->id = nextId++;
    frame->generation = job.generation;
    frame->spp = job.spp;
    frame->kind = job.kind;
    std::shared_ptr<const FilmImage> image = job.image.film;
    frame->width = image->width;
    frame->height = image->height;
    Json stats = Json::parse(job.statsJson);
    bool full = image->width == width_ && image->height == height_;
    try {
      double denoiseMs = -1.0;
      // Not a frame a waiting edit makes stale: the edit's first frame must not queue behind
      // a denoise (about a second for 512^2 on 2 CPU cores).
      if (full && !editsWaiting_) {
        image = Displayed(job.image, &denoiseMs);
        job.image.film = image;  // shown and kept with its denoised layer
      }
      bool denoised = denoise_ && !image->denoised.empty();
      frame->jpeg = EncodeJpeg(image->width, image->height,
                               DisplayPixels(denoised ? image->denoised : image->rgb,
                                             Display()),
                               settings_.jpegQuality);
      if (denoiseMs >= 0.0) {  // a re-encode keeps its frame's
        stats["denoise_ms"] = denoiseMs;
        const DenoiseSettings& used = denoiser_->Settings();
        stats["denoise_variance"] = used.calibrateVariance ? "calibrated" : "sample";
        stats["denoise_emission"] = used.keepSeenEmission ? "keep" : "filter";
      }
      if (!denoised) {
        for (const char* key : {"denoise_ms", "denoise_variance", "denoise_emission"})
          stats.erase(key);
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pathtracer: serve: %s\n", e.what());
    }
    if (job.editReceived != LoopClock::time_point()) {
      stats["edit_to_frame_ms"] = MsFrom(job.editReceived, LoopClock::now());
    } else {
      stats.erase("edit_to_frame_ms");  // a later frame of the generation, or a re-encode
    }
    stats["frame"] = frame->id;
    stats["kind"] = frame->kind;
    frame->statsJson = stats.dump();
    lock.lock();
    frame_ = std::move(frame);
    shownImage_ = job.image;
    // A re-encode of the last full frame keeps the denoised layer it may have gained.
    if (job.kind == "render" || (job.kind == "display" && full)) image_ = job.image;
    progressJson_ = frame_->statsJson;
    frameReady_.notify_all();
    lock.unlock();
    feed_.Bump(ChangeFeed::kProgress);
    lock.lock();
  }
}

// Coarse frames are never denoised (they carry no features); a denoiser that fails says so and
// the frame shows the film.
std::shared_ptr<const FilmImage> LiveRender::Displayed(const RenderedImage& image, double* ms) {
  *ms = -1.0;
  const std::shared_ptr<const FilmImage>& film = image.film;
  if (!denoise_ || !denoiser_ || !film->denoised.empty()) return film;
  if (settings_.denoiseSettings) denoiser_->SetSettings(settings_.denoiseSettings(image.sampler));
  if (std::string problem = DenoiseInputProblem(*film); !problem.empty()) {
    std::fprintf(stderr, "pathtracer: serve: not denoised: %s\n", problem.c_str());
    return film;
  }
  auto denoised = std::make_shared<FilmImage>(*film);
  denoiser_->Denoise(*denoised);
  *ms = denoiser_->LastMs();
  return denoised;
}

}  // namespace pt
