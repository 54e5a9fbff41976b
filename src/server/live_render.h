// The render behind the live preview: one thread renders the scene progressively on a
// RenderSession, a sample per pixel at a time; edits from any thread (camera, flags,
// materials, object moves, lighting) are checked at once and applied between waves (a wave
// under way is dropped between bounces), restarting the accumulation; while edits keep coming
// each restart first renders a coarse frame at reduced resolution, then refines at full
// resolution. An encoder thread turns the film into the frame every client reads. The server
// holds the one state every page shows (camera, options, display, selection, lighting) and
// announces each change on its ChangeFeed.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "src/denoise/denoiser.h"
#include "src/integrator/render_session.h"
#include "src/io/tone_mapping.h"
#include "src/server/change_feed.h"
#include "src/server/scene_document.h"
#include "src/server/scene_objects.h"

namespace pt {

using MakeSessionFn = std::function<std::unique_ptr<RenderSession>(
    const Scene&, const RenderOptions&, const RenderCallbacks&)>;

// A camera the page offers to switch to: the scene's own first, then a glTF file's.
struct NamedCamera {
  std::string name;
  CameraDesc camera;
};

struct LiveSettings {
  RenderOptions options;       // the flags as the command line set them
  double framesPerSecond = 5;  // updates while converging; an edit's first frame goes at once
  int jpegQuality = 88;
  DisplaySettings display;     // --exposure, --tonemap
  // A restart whose full-resolution sample would take longer than this first shows a coarse
  // frame that takes about this long (0: never coarse).
  double coarseFrameMs = 25.0;
  std::vector<NamedCamera> cameras;  // after the scene's own camera (a model file's)
  std::string environmentFolder;     // where the lighting picker's maps are listed from
  // The denoiser frames may be shown through (options "denoise": display only), or null: with
  // one, the film keeps the features and half films it reads; without, the page hides the toggle.
  std::function<std::unique_ptr<Denoiser>()> makeDenoiser;
  // The denoiser's settings for the sampler a frame was rendered with (null: the denoiser's
  // own throughout): the variance rule follows the page's sampler flag as the CLI's default does.
  std::function<DenoiseSettings(SamplerKind)> denoiseSettings;
  bool denoise = false;  // frames denoised from the start (--serve --denoise)
};

// A tone-mapped frame as the page receives it, with the statistics it was made with.
struct PreviewFrame {
  uint64_t id = 0;          // grows with every frame
  uint64_t generation = 0;  // grows with every applied edit that restarts the accumulation
  uint32_t spp = 0;
  std::string kind;         // "coarse" (reduced resolution), "render", "display" (re-encoded)
  int width = 0, height = 0;
  std::string jpeg;
  std::string statsJson;
};

// An edit the preview refuses: malformed (400), no such object (404), or a value the scene
// cannot take (422, the loader's message). `field` names the control it came from.
struct EditError : std::runtime_error {
  EditError(int status, const std::string& message, std::string field = "")
      : std::runtime_error(message), status(status), field(std::move(field)) {}
  int status;
  std::string field;
};

// What an edit answers: the generation whose frames show it, and whether it restarts the film.
struct EditAnswer {
  uint64_t generation = 0;
  bool restarts = false;
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
  // The last full-resolution image (linear), for downloads and the save at exit.
  std::shared_ptr<const FilmImage> LatestImage() const;
  std::string DescribeJson() const;  // objects, materials, cameras, maps, settings, flags
  std::string StateJson() const;     // camera, options, display, selection, lighting
  std::string ProgressJson() const;  // the latest frame's statistics and the render's status
  std::string SceneText() const;     // the edited scene file
  PickResult Pick(float x, float y) const;
  int Width() const { return width_; }
  int Height() const { return height_; }
  DisplaySettings Display() const;
  bool Denoising() const { return denoiseAvailable_ && denoise_; }  // frames shown denoised
  ChangeFeed& Feed() { return feed_; }
  // The selected object's outline as an RGBA PNG of at most maxSide pixels a side (empty when
  // nothing is selected): src/server/live_outline.cpp.
  std::string OutlinePng(int maxSide) const;

  // ---- Edits (any thread) ----
  // Each is checked now (throws EditError) and applied by the render thread before its next
  // wave.
  EditAnswer EditCamera(const Json& fields);
  EditAnswer ChooseCamera(size_t index);  // 0: the scene's own camera
  EditAnswer FrameSelected();             // the camera turned to fit the selected object
  // compact, sort, integrator, specialize, light_sampler, max_depth, spp; denoise (display
  // only: true shows every full-resolution frame denoised, when the preview has a denoiser).
  EditAnswer EditOptions(const Json& fields);
  EditAnswer EditMaterial(size_t index, const Json& fields);
  // An instance object is re-placed through the top level (RebuildTopLevel, no mesh touched);
  // any other object is loaded again at its new place and the scene rebuilt.
  EditAnswer MoveObject(size_t index, vec3 delta);
  // {map: "scene" | "none" | a listed file name, strength, rotation}: fields not given stay.
  EditAnswer EditLighting(const Json& fields);
  // {exposure, tone_mapping}: display only, the current film is encoded again.
  void EditDisplay(const Json& fields);
  void SetExposure(float stops);
  // The object picked at pixel (x, y), or none (object < 0).
  void Select(int object, int material);

  void Stop();
  // After Stop: the film as it stands, or the last full frame's image when the film holds no
  // whole sample (an edit had just restarted it); null when there is none. *spp: its samples.
  // With denoising on, the image carries the denoised layer.
  std::shared_ptr<const FilmImage> FinalImage(uint32_t* spp);

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
    std::optional<SceneDesc> lighting;  // environment, background, the sky's sun
  };
  // A film image and the sampler it was rendered with (which the denoiser's variance rule
  // follows): kept together wherever an image waits to be shown or saved.
  struct RenderedImage {
    std::shared_ptr<const FilmImage> film;
    SamplerKind sampler = SamplerKind::kIndependent;
  };
  // The encoder's input: the newest film image waiting to become a frame.
  struct Encoding {
    RenderedImage image;
    uint64_t generation = 0;
    uint32_t spp = 0;
    std::string kind;
    std::string statsJson;
    std::chrono::steady_clock::time_point editReceived;  // set on a generation's first frame
    bool waiting = false;
  };

  EditAnswer Queue(const std::function<void(Pending&)>& edit, ChangeFeed::Topic topic);
  EditAnswer QueueCamera(const Json& fields, bool replace, int choice);
  void RenderLoop();
  bool ApplyEdits();
  void ApplySceneEdits(const Pending& p);  // under an exclusive sceneMutex_
  void ApplyLighting(const SceneDesc& lit);
  void RenderCoarseFrame();
  void RenderPass();
  void Publish(const std::string& statsJson, bool coarse, std::shared_ptr<const FilmImage> image);
  void EncodeLoop();
  void EncodeAgain();  // the shown image as a frame again (a display setting changed)
  // The frame's image: the film's, or with the denoised layer added when denoising is on (its
  // time in ms in *ms, else -1). Encoder thread (or after Stop) only.
  std::shared_ptr<const FilmImage> Displayed(const RenderedImage& image, double* ms);
  std::string StatsJson(const RenderStats& now, double passMs, uint32_t passSpp) const;
  Json ListMaps() const;

  // Guarded by docMutex_: the document, the edits not yet applied and the state pages show.
  mutable std::mutex docMutex_;
  SceneDocument document_;
  std::unique_ptr<Pending> pending_;
  uint64_t requestedGeneration_ = 0;
  RenderOptions requestedOptions_;  // the flags as the latest edit left them
  int cameraChoice_ = 0;            // LiveSettings::cameras index (0: the scene's), -1: moved
  int selectedObject_ = -1, selectedMaterial_ = -1;
  std::string lightingMap_ = "scene";  // "scene", "none" or a listed map's name
  DisplaySettings display_;
  std::atomic<bool> denoise_{false};  // frames shown denoised (with a denoiser only)
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
  std::vector<NamedCamera> cameras_;  // the scene's own camera, then settings_.cameras
  int width_ = 0, height_ = 0;
  std::atomic<uint32_t> spp_{0};
  uint32_t targetSpp_ = 0;
  uint64_t generation_ = 0;
  bool firstFrameOfGeneration_ = true, firstFullFrame_ = true;
  bool filmHoldsCoarse_ = false;
  std::atomic<bool> coarseUnderWay_{false};  // its waves are not dropped by newer edits
  RenderStats generationStart_, lastPassEnd_;
  double lastPassMs_ = 0.0, msPerSpp_ = 0.0;  // msPerSpp_: a full-resolution sample, measured
  // A newer edit dropped the last generation's first full-resolution sample: edits come faster
  // than samples (a drag, a busy machine), so the next edits show as coarse frames.
  bool editsOutpaceSamples_ = false;
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
  RenderedImage image_;       // the last full-resolution image
  RenderedImage shownImage_;  // the image of frame_ (maybe coarse)
  std::string progressJson_ = "{}";               // guarded by frameMutex_
  std::unique_ptr<Denoiser> denoiser_;  // used by the encoder thread only (and after Stop)
  bool denoiseAvailable_ = false;       // denoiser_ was made (read by every thread)

  ChangeFeed feed_;
  std::thread renderThread_, encodeThread_;
};

}  // namespace pt
