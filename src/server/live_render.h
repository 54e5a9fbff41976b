// The render behind the live preview: one thread renders the scene progressively on a
// RenderSession, a sample per pixel at a time; edits from any thread (camera, flags,
// materials, object moves) are checked at once and applied between waves, restarting the
// accumulation; an encoder thread turns the film into the frame every client reads.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <map>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "src/denoise/denoiser.h"
#include "src/integrator/render_session.h"
#include "src/server/scene_document.h"
#include "src/server/scene_objects.h"

namespace pt {

using MakeSessionFn = std::function<std::unique_ptr<RenderSession>(
    const Scene&, const RenderOptions&, const RenderCallbacks&)>;

struct LiveSettings {
  RenderOptions options;       // the flags as the command line set them
  double framesPerSecond = 5;  // updates while converging; an edit's first frame goes at once
  int jpegQuality = 88;
  // The denoiser frames may be shown through (options "denoise"), or null: with one, the film
  // keeps the features and half films it reads.
  std::function<std::unique_ptr<Denoiser>()> makeDenoiser;
  bool denoise = false;  // frames denoised from the start (--serve --denoise)
};

// A tone-mapped frame as the page receives it, with the statistics it was made with.
struct PreviewFrame {
  uint64_t id = 0;          // grows with every frame
  uint64_t generation = 0;  // grows with every applied edit that restarts the accumulation
  uint32_t spp = 0;
  std::string jpeg;
  std::string statsJson;
};

// An edit the preview refuses: malformed (400), no such object (404), or a value the scene
// cannot take (422, the loader's message).
struct EditError : std::runtime_error {
  EditError(int status, const std::string& message)
      : std::runtime_error(message), status(status) {}
  int status;
};

class LiveRender {
 public:
  // The Scene must be built from the document's scene. Starts rendering at once.
  LiveRender(SceneDocument document, Scene scene, MakeSessionFn makeSession,
             LiveSettings settings);
  ~LiveRender();
  LiveRender(const LiveRender&) = delete;
  LiveRender& operator=(const LiveRender&) = delete;

  // ---- Reading (any thread) ----
  std::shared_ptr<const PreviewFrame> LatestFrame() const;
  // The latest frame once one newer than `after` exists, or when the timeout passes.
  std::shared_ptr<const PreviewFrame> WaitForFrame(uint64_t after, std::chrono::milliseconds timeout);
  std::shared_ptr<const FilmImage> LatestImage() const;  // linear, for image downloads
  std::string DescribeJson() const;  // objects, materials, camera, settings, flags
  std::string SceneText() const;     // the edited scene file
  PickResult Pick(float x, float y) const;
  int Width() const { return width_; }
  int Height() const { return height_; }

  // ---- Edits (any thread) ----
  // Each is checked now (throws EditError) and applied by the render thread before its next
  // wave; returns the generation whose frames show it.
  uint64_t EditCamera(const Json& fields);
  // compact, sort, integrator, specialize, max_depth, spp; denoise (display only: true shows
  // every frame denoised, when the preview has a denoiser).
  uint64_t EditOptions(const Json& fields);
  uint64_t EditMaterial(size_t index, const Json& fields);
  // An instance object is re-placed through the top level (RebuildTopLevel, no mesh touched);
  // any other object is loaded again at its new place and the scene rebuilt.
  uint64_t MoveObject(size_t index, vec3 delta);
  void SetExposure(float stops);  // display only: the current film is encoded again

  void Stop();

 private:
  // Edits checked by the HTTP threads, waiting for the render thread. Later edits of the same
  // thing replace earlier ones: the document already holds their sum.
  struct Pending {
    bool restart = false;
    std::chrono::steady_clock::time_point firstReceived;
    std::optional<CameraDesc> camera;
    std::optional<RenderOptions> options;
    std::optional<int> maxDepth;
    std::optional<uint32_t> spp;
    std::map<size_t, Material> materials;
    std::map<size_t, SceneDesc> moves;  // object -> its shapes at the new place
    std::map<size_t, glm::dmat4> placements;  // SceneDesc::instances index -> its new toWorld
  };
  struct Encoding;

  uint64_t Queue(const std::function<void(Pending&)>& edit);
  void RenderLoop();
  bool ApplyEdits();
  void ApplySceneEdits(const Pending& p);  // under an exclusive sceneMutex_
  void RenderPass();
  void Publish(const std::string& statsJson);
  void EncodeLoop();
  void EncodeAgain();  // the current film as a frame again (a display setting changed)
  // The frame's image: the film's, or with --denoise's layer added (its time in ms, or -1).
  std::shared_ptr<const FilmImage> Displayed(std::shared_ptr<const FilmImage> image, double* ms);
  std::string StatsJson(const RenderStats& now, double passMs, uint32_t passSpp) const;

  // Guarded by docMutex_: the document and the edits not yet applied.
  mutable std::mutex docMutex_;
  SceneDocument document_;
  std::unique_ptr<Pending> pending_;
  uint64_t requestedGeneration_ = 0;
  RenderOptions requestedOptions_;  // the flags as the latest edit left them
  std::atomic<bool> editsWaiting_{false};  // an edit that restarts the film waits

  // Written by the render thread only, under an exclusive sceneMutex_ (picks read them).
  mutable std::shared_mutex sceneMutex_;
  Scene scene_;
  SceneObjects objects_;
  Camera camera_;
  RenderOptions options_;
  std::unique_ptr<RenderSession> session_;

  // The render thread's own state.
  LiveSettings settings_;
  int width_ = 0, height_ = 0;
  uint32_t spp_ = 0, targetSpp_ = 0;
  uint64_t generation_ = 0;
  bool firstFrameOfGeneration_ = true;
  RenderStats generationStart_, lastPassEnd_;
  double lastPassMs_ = 0.0;
  // What the edits cost: full scene rebuilds, top-level rebuilds (instance moves alone), and
  // the last rebuild's time; reported with every frame's statistics.
  uint64_t sceneRebuilds_ = 0, topLevelRebuilds_ = 0;
  double lastRebuildMs_ = 0.0;
  uint32_t lastPassSpp_ = 0;
  std::chrono::steady_clock::time_point lastPublish_, editReceived_;

  std::atomic<bool> stop_{false};
  std::mutex wakeMutex_;
  std::condition_variable wake_;
  bool wakeCalls_ = false;  // guarded by wakeMutex_: an edit of any kind waits

  // Frames: the encoder's input slot and the published frame.
  std::unique_ptr<Encoding> encoding_;
  mutable std::mutex frameMutex_;
  std::condition_variable frameReady_;
  std::shared_ptr<const PreviewFrame> frame_;
  std::shared_ptr<const FilmImage> image_;
  std::atomic<float> exposure_{0.0f};
  std::unique_ptr<Denoiser> denoiser_;  // used by the encoder thread only
  std::atomic<bool> denoise_{false};

  std::thread renderThread_, encodeThread_;
};

// Linear radiance times 2^stops, sRGB-encoded and clamped to 8 bits (as PNG output is).
std::vector<uint8_t> ToneMap(const FilmImage& image, float stops);

}  // namespace pt
