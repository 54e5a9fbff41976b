// LiveRender: construction, what clients read, and the edits they send (checked here, on the
// calling thread; applied by the render thread, src/server/live_render_loop.cpp).
#include "src/server/live_render.h"

#include <cmath>
#include <cstdio>

#include "src/io/scene_loader.h"

namespace pt {

using LiveClock = std::chrono::steady_clock;

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
  document_.ResolveCamera(scene_.desc.camera);  // a glTF or automatic camera, as positioned
  cameras_.push_back(NamedCamera{"the scene's camera", scene_.desc.camera});
  cameras_.insert(cameras_.end(), settings_.cameras.begin(), settings_.cameras.end());
  display_ = settings_.display;
  width_ = scene_.desc.render.width;
  height_ = scene_.desc.render.height;
  targetSpp_ = uint32_t(scene_.desc.render.spp);
  options_.crop = CropWindow{};
  // The sampler in force, named in the state (the option, else the scene's render.sampler).
  options_.sampler = options_.sampler.value_or(scene_.desc.render.sampler);
  options_.adaptive = Toggle::kOff;
  if (settings_.makeDenoiser) {
    denoiser_ = settings_.makeDenoiser();
    denoiseAvailable_ = denoiser_ != nullptr;
    options_.featureBuffers = options_.halfFilms = true;
    denoise_ = settings_.denoise;
  }
  requestedOptions_ = options_;
  RenderCallbacks callbacks;
  callbacks.shouldStop = [this] { return editsWaiting_.load() || stop_.load(); };
  // A newer edit drops the full-resolution wave under way; a coarse frame is short and is
  // what keeps frames coming while the view moves.
  callbacks.abandonWave = [this] {
    return stop_.load() || (editsWaiting_.load() && !coarseUnderWay_.load());
  };
  session_ = makeSession(scene_, options_, callbacks);
  generationStart_ = lastPassEnd_ = session_->Stats();
  lastPublish_ = LiveClock::now();
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
  feed_.Close();
  if (renderThread_.joinable()) renderThread_.join();
  if (encodeThread_.joinable()) encodeThread_.join();
}

std::shared_ptr<const FilmImage> LiveRender::FinalImage(uint32_t* spp) {
  *spp = 0;
  if (renderThread_.joinable()) return nullptr;  // only after Stop
  RenderedImage image;
  if (filmHoldsCoarse_ || spp_ == 0) {
    std::lock_guard<std::mutex> lock(frameMutex_);
    if (image_.film) *spp = image_.film->samples.empty() ? 0u : image_.film->samples[0];
    image = image_;
  } else {
    *spp = spp_;
    image = RenderedImage{std::make_shared<const FilmImage>(session_->Image()),
                          options_.sampler.value_or(SamplerKind::kIndependent)};
  }
  double ms;  // the encoder has stopped: the denoiser is free
  return image.film ? Displayed(image, &ms) : image.film;
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
  return image_.film;
}

std::string LiveRender::ProgressJson() const {
  std::lock_guard<std::mutex> lock(frameMutex_);
  return progressJson_;
}

std::string LiveRender::SceneText() const {
  std::lock_guard<std::mutex> lock(docMutex_);
  return document_.Text();
}

DisplaySettings LiveRender::Display() const {
  std::lock_guard<std::mutex> lock(docMutex_);
  return display_;
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

EditAnswer LiveRender::Queue(const std::function<void(Pending&)>& edit, ChangeFeed::Topic topic) {
  EditAnswer answer;
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    bool before = pending_->restart;
    pending_->restart = false;
    try {
      edit(*pending_);
    } catch (const SceneError& e) {
      pending_->restart = before;
      throw EditError(422, e.what());
    } catch (...) {
      pending_->restart = before;
      throw;
    }
    answer.restarts = pending_->restart;
    pending_->restart = pending_->restart || before;
    if (answer.restarts) {
      if (!editsWaiting_) pending_->firstReceived = LiveClock::now();
      ++requestedGeneration_;
    }
    answer.generation = requestedGeneration_;
    {
      std::lock_guard<std::mutex> wakeLock(wakeMutex_);
      editsWaiting_ = editsWaiting_ || answer.restarts;
      wakeCalls_ = true;
    }
  }
  wake_.notify_all();
  feed_.Bump(topic);
  return answer;
}

EditAnswer LiveRender::QueueCamera(const Json& fields, bool replace, int choice) {
  return Queue(
      [&](Pending& p) {
        p.camera = document_.EditCamera(fields, replace);
        p.restart = true;
        cameraChoice_ = choice;
      },
      ChangeFeed::kState);
}

EditAnswer LiveRender::EditCamera(const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the camera must be a JSON object");
  return QueueCamera(fields, false, -1);
}

EditAnswer LiveRender::ChooseCamera(size_t index) {
  if (index >= cameras_.size()) {
    throw EditError(404, "no camera " + std::to_string(index) + " (the scene offers " +
                             std::to_string(cameras_.size()) + ")");
  }
  return QueueCamera(CameraDescJson(cameras_[index].camera), true, int(index));
}

EditAnswer LiveRender::FrameSelected() {
  int object;
  Json camera;
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    object = selectedObject_;
    camera = document_.CameraJson();
  }
  if (object < 0) throw EditError(409, "nothing is selected to frame");
  Aabb box;
  {
    std::shared_lock<std::shared_mutex> lock(sceneMutex_);
    box = ObjectBounds(scene_.desc, objects_.Shapes(size_t(object)));
  }
  if (!(box.lo.x <= box.hi.x)) throw EditError(409, "the selected object has no shapes to frame");
  // The view direction kept; the bounds' sphere fits the narrower field of view, 10% spare.
  auto read = [&](const char* key) {
    const Json& v = camera[key];
    return vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
  };
  vec3 position = read("position");
  vec3 forward = glm::normalize(read("look_at") - position);
  float fovY = glm::radians(camera.value("fov_y", 45.0f));
  float aspect = float(width_) / float(std::max(1, height_));
  float halfFov = std::min(0.5f * fovY, std::atan(std::tan(0.5f * fovY) * aspect));
  vec3 center = 0.5f * (box.lo + box.hi);
  float radius = std::max(1e-4f, 0.5f * glm::length(box.hi - box.lo));
  float distance = 1.1f * radius / std::sin(halfFov);
  Json fields = {{"position", DocumentVec3(center - forward * distance)},
                 {"look_at", DocumentVec3(center)}};
  return QueueCamera(fields, false, -1);
}

EditAnswer LiveRender::EditMaterial(size_t index, const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the material must be a JSON object");
  return Queue(
      [&](Pending& p) {
        if (index >= document_.MaterialCount()) {
          throw EditError(404, "no material " + std::to_string(index) + " in the scene file");
        }
        p.materials[index] = document_.EditMaterial(index, fields);
        p.restart = true;
      },
      ChangeFeed::kScene);
}

EditAnswer LiveRender::MoveObject(size_t index, vec3 delta) {
  if (!IsFinite(delta)) throw EditError(400, "the move must be 3 finite numbers");
  return Queue(
      [&](Pending& p) {
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
      },
      ChangeFeed::kScene);
}

void LiveRender::Select(int object, int material) {
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    if (object >= int(objects_.Count())) throw EditError(404, "no object " + std::to_string(object));
    selectedObject_ = object < 0 ? -1 : object;
    selectedMaterial_ = object < 0 ? -1 : material;
  }
  feed_.Bump(ChangeFeed::kState);
}

void LiveRender::SetExposure(float stops) { EditDisplay(Json{{"exposure", stops}}); }

void LiveRender::EditDisplay(const Json& fields) {
  if (!fields.is_object()) throw EditError(400, "the display settings must be a JSON object");
  DisplaySettings display = Display();
  for (const auto& [key, value] : fields.items()) {
    if (key == "exposure") {
      float stops = value.is_number() ? value.get<float>() : NAN;
      if (!std::isfinite(stops) || std::fabs(stops) > 20.0f) {
        throw EditError(400, "exposure must be a number of stops in [-20, 20]", "exposure");
      }
      display.exposure = stops;
    } else if (key == "tone_mapping") {
      if (!value.is_string() || !ParseToneMapping(value.get<std::string>(), &display.toneMapping)) {
        throw EditError(400, "bad value for tone_mapping: " + value.dump() + " (expected clip|agx)",
                        "tone_mapping");
      }
    } else {
      throw EditError(400, "unknown display setting \"" + key +
                               "\" (expected exposure or tone_mapping)");
    }
  }
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    display_ = display;
  }
  EncodeAgain();
  feed_.Bump(ChangeFeed::kState);
}

}  // namespace pt
