#include "src/server/live_render.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "src/lights/light_table.h"
#include "src/scene/instances.h"

namespace pt {

using Clock = std::chrono::steady_clock;

namespace {

double MsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// A pass aims at this much render time, so frames keep coming while the film converges.
constexpr double kPassTargetMs = 60.0;
constexpr uint32_t kMaxSamplesPerPass = 16;

}  // namespace

// The encoder's input: the newest film image waiting to become a frame.
struct LiveRender::Encoding {
  std::shared_ptr<const FilmImage> image;
  uint64_t generation = 0;
  uint32_t spp = 0;
  std::string statsJson;
  Clock::time_point editReceived;  // set on a generation's first frame
  bool waiting = false;
};

std::vector<uint8_t> ToneMap(const FilmImage& image, float stops) {
  float scale = std::exp2(stops);
  std::vector<uint8_t> out(image.rgb.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = LinearToSrgb8(image.rgb[i] * scale);
  return out;
}

LiveRender::LiveRender(SceneDocument document, Scene scene, MakeSessionFn makeSession,
                       LiveSettings settings)
    : document_(std::move(document)),
      pending_(std::make_unique<Pending>()),
      scene_(std::move(scene)),
      objects_(document_, scene_.desc),
      camera_(scene_.camera),
      options_(settings.options),
      settings_(std::move(settings)),
      encoding_(std::make_unique<Encoding>()) {
  width_ = scene_.desc.render.width;
  height_ = scene_.desc.render.height;
  targetSpp_ = uint32_t(scene_.desc.render.spp);
  options_.crop = CropWindow{};
  options_.adaptive = Toggle::kOff;
  requestedOptions_ = options_;
  RenderCallbacks callbacks;
  callbacks.shouldStop = [this] { return editsWaiting_.load() || stop_.load(); };
  session_ = makeSession(scene_, options_, callbacks);
  generationStart_ = lastPassEnd_ = session_->Stats();
  lastPublish_ = Clock::now();
  renderThread_ = std::thread([this] { RenderLoop(); });
  encodeThread_ = std::thread([this] { EncodeLoop(); });
}

LiveRender::~LiveRender() { Stop(); }

void LiveRender::Stop() {
  {
    std::lock_guard<std::mutex> lock(wakeMutex_);
    stop_ = true;
  }
  wake_.notify_all();
  {
    std::lock_guard<std::mutex> lock(frameMutex_);
  }
  frameReady_.notify_all();
  if (renderThread_.joinable()) renderThread_.join();
  if (encodeThread_.joinable()) encodeThread_.join();
}

// ---- Reading ----------------------------------------------------------------------------------

std::shared_ptr<const PreviewFrame> LiveRender::LatestFrame() const {
  std::lock_guard<std::mutex> lock(frameMutex_);
  return frame_;
}

std::shared_ptr<const PreviewFrame> LiveRender::WaitForFrame(uint64_t after,
                                                      std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(frameMutex_);
  frameReady_.wait_for(lock, timeout, [&] { return stop_ || (frame_ && frame_->id > after); });
  return frame_;
}

std::shared_ptr<const FilmImage> LiveRender::LatestImage() const {
  std::lock_guard<std::mutex> lock(frameMutex_);
  return image_;
}

std::string LiveRender::SceneText() const {
  std::lock_guard<std::mutex> lock(docMutex_);
  return document_.Text();
}

PickResult LiveRender::Pick(float x, float y) const {
  if (!(x >= 0.0f && x < float(width_) && y >= 0.0f && y < float(height_))) {
    throw EditError(400, "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                             ") is outside the " + std::to_string(width_) + "x" +
                             std::to_string(height_) + " image");
  }
  std::shared_lock<std::shared_mutex> lock(sceneMutex_);
  return PickPixel(scene_, camera_, width_, height_, x, y, objects_);
}

// ---- Edits ------------------------------------------------------------------------------------

uint64_t LiveRender::Queue(const std::function<void(Pending&)>& edit) {
  std::lock_guard<std::mutex> lock(docMutex_);
  try {
    edit(*pending_);
  } catch (const SceneError& e) {
    throw EditError(422, e.what());
  }
  if (pending_->restart) {
    if (!editsWaiting_) pending_->firstReceived = Clock::now();
    ++requestedGeneration_;
  }
  {
    std::lock_guard<std::mutex> wakeLock(wakeMutex_);
    editsWaiting_ = editsWaiting_ || pending_->restart;
    wakeCalls_ = true;
  }
  wake_.notify_all();
  return requestedGeneration_;
}

uint64_t LiveRender::EditCamera(const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the camera must be a JSON object");
  return Queue([&](Pending& p) {
    p.camera = document_.EditCamera(fields);
    p.restart = true;
  });
}

uint64_t LiveRender::EditMaterial(size_t index, const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the material must be a JSON object");
  return Queue([&](Pending& p) {
    if (index >= document_.MaterialCount()) {
      throw EditError(404, "no material " + std::to_string(index) + " in the scene file");
    }
    p.materials[index] = document_.EditMaterial(index, fields);
    p.restart = true;
  });
}

uint64_t LiveRender::MoveObject(size_t index, vec3 delta) {
  if (!IsFinite(delta)) throw EditError(400, "the move must be 3 finite numbers");
  return Queue([&](Pending& p) {
    if (index >= objects_.Count()) throw EditError(404, "no object " + std::to_string(index));
    if (int instance = objects_.InstanceOf(index); instance >= 0) {
      SceneDocument::MovedInstance moved = document_.TranslatedInstance(index, delta);
      document_.SetObject(index, std::move(moved.object));
      p.placements[size_t(instance)] = moved.toWorld;
      p.restart = true;
      return;
    }
    SceneDocument::MovedObject moved = document_.TranslatedObject(index, delta);
    if (!objects_.Fits(index, moved.loaded)) {
      throw EditError(422, "object " + std::to_string(index) +
                               " would change its shapes there (degenerate after the move)");
    }
    document_.SetObject(index, std::move(moved.object));
    p.moves[index] = std::move(moved.loaded);
    p.restart = true;
  });
}

void LiveRender::SetExposure(float stops) {
  if (!std::isfinite(stops) || std::fabs(stops) > 20.0f) {
    throw EditError(400, "exposure must be a number of stops in [-20, 20]");
  }
  exposure_ = stops;
  std::lock_guard<std::mutex> lock(frameMutex_);
  if (!frame_ || !image_) return;
  encoding_->image = image_;
  encoding_->generation = frame_->generation;
  encoding_->spp = frame_->spp;
  encoding_->statsJson = frame_->statsJson;
  encoding_->waiting = true;
  frameReady_.notify_all();
}

// ---- The render thread ------------------------------------------------------------------------

void LiveRender::RenderLoop() {
  while (!stop_) {
    try {
      ApplyEdits();
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
  if (p->spp) targetSpp_ = *p->spp;
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
  firstFrameOfGeneration_ = true;
  editReceived_ = p->firstReceived;
  generationStart_ = lastPassEnd_ = session_->Stats();
  return true;
}

// Moves and materials, by the cheapest update that covers them: instance moves alone re-place
// through the top level, any other move rebuilds the scene.
void LiveRender::ApplySceneEdits(const Pending& p) {
  auto t0 = Clock::now();
  for (const auto& [index, toWorld] : p.placements) UpdateInstanceTransform(scene_, index, toWorld);
  for (const auto& [index, moved] : p.moves) objects_.Place(index, moved, scene_.desc);
  for (const auto& [index, material] : p.materials) scene_.desc.materials[index] = material;
  if (!p.moves.empty()) {
    scene_ = BuildScene(std::move(scene_.desc));
    session_->SceneChanged();
    ++sceneRebuilds_;
  } else {
    if (!p.placements.empty()) RebuildTopLevel(scene_);
    if (!p.materials.empty()) BuildLightTable(scene_);  // after the top level: its bounds
    if (!p.placements.empty()) {
      session_->TopLevelChanged();
      ++topLevelRebuilds_;
    }
    if (!p.materials.empty()) session_->MaterialsChanged();
  }
  if (!p.moves.empty() || !p.placements.empty()) lastRebuildMs_ = MsBetween(t0, Clock::now());
}

void LiveRender::RenderPass() {
  double msPerSpp = 0.0;
  RenderStats before = lastPassEnd_;
  uint64_t passSamples = uint64_t(width_) * height_;
  uint32_t lastCount = std::max<uint32_t>(1, lastPassSpp_);
  if (lastPassMs_ > 0.0) msPerSpp = lastPassMs_ / lastCount;
  uint32_t count = msPerSpp > 0.0 ? uint32_t(std::clamp(kPassTargetMs / msPerSpp, 1.0,
                                                        double(kMaxSamplesPerPass)))
                                  : 1u;
  count = std::min(count, targetSpp_ - spp_);
  uint64_t done;
  {
    std::shared_lock<std::shared_mutex> lock(sceneMutex_);
    done = session_->RenderRange(spp_, spp_ + count);
  }
  if (done < passSamples * count) return;  // an edit stopped it: the film starts over
  spp_ += count;
  RenderStats now = session_->Stats();
  lastPassMs_ = now.renderMs - before.renderMs;
  lastPassSpp_ = count;
  std::string stats = StatsJson(now, lastPassMs_, count);
  lastPassEnd_ = now;
  Publish(stats);
}

void LiveRender::Publish(const std::string& statsJson) {
  auto now = Clock::now();
  bool due = firstFrameOfGeneration_ || spp_ >= targetSpp_ ||
             MsBetween(lastPublish_, now) >= 1000.0 / settings_.framesPerSecond;
  if (!due) return;
  auto image = std::make_shared<const FilmImage>(session_->Image());
  lastPublish_ = now;
  std::lock_guard<std::mutex> lock(frameMutex_);
  encoding_->image = std::move(image);
  encoding_->generation = generation_;
  encoding_->spp = spp_;
  encoding_->statsJson = statsJson;
  encoding_->editReceived = firstFrameOfGeneration_ ? editReceived_ : Clock::time_point();
  encoding_->waiting = true;
  firstFrameOfGeneration_ = false;
  frameReady_.notify_all();
}

// ---- The encoder thread -----------------------------------------------------------------------

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
    frame->statsJson = job.statsJson;
    try {
      frame->jpeg = EncodeJpeg(job.image->width, job.image->height,
                               ToneMap(*job.image, exposure_), settings_.jpegQuality);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pathtracer: serve: %s\n", e.what());
    }
    if (job.editReceived != Clock::time_point()) {
      double ms = MsBetween(job.editReceived, Clock::now());
      Json stats = Json::parse(frame->statsJson);
      stats["edit_to_frame_ms"] = ms;
      frame->statsJson = stats.dump();
    }
    lock.lock();
    frame_ = std::move(frame);
    image_ = job.image;
    frameReady_.notify_all();
  }
}

}  // namespace pt
