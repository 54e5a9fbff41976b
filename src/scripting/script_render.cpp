#include "src/scripting/script_render.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "src/app/denoise_step.h"
#include "src/app/run_steps.h"
#include "src/distributed/chunked_render.h"

namespace pt {
namespace {

using ScriptRenderClock = std::chrono::steady_clock;

double MsFrom(ScriptRenderClock::time_point start) {
  return std::chrono::duration<double, std::milli>(ScriptRenderClock::now() - start).count();
}

}  // namespace

// The script's stop callback, and --time-limit measured from the first wave (after the scene's
// upload), as the CLI's StopCheck measures it.
class ScriptStop {
 public:
  ScriptStop(std::function<bool()> user, double limitSeconds)
      : user_(std::move(user)), limit_(limitSeconds) {}
  bool operator()() {
    if (user_ && user_()) stoppedByUser_ = true;
    if (stoppedByUser_) return true;
    if (!start_) start_ = ScriptRenderClock::now();
    if (limit_ > 0.0 && MsFrom(*start_) >= limit_ * 1000.0) timeUp_ = true;
    return timeUp_;
  }
  bool StoppedByUser() const { return stoppedByUser_; }
  bool TimeUp() const { return timeUp_; }

 private:
  std::function<bool()> user_;
  double limit_;
  std::optional<ScriptRenderClock::time_point> start_;
  bool stoppedByUser_ = false, timeUp_ = false;
};

namespace {


struct ScriptSetup {
  BackendKind backend = BackendKind::kCpu;
  SessionFactory factory = nullptr;
  RenderOptions options;
};

ScriptSetup SetUpScriptRender(const ScriptRequest& request, const Scene& scene, const AppBackends& backends) {
  ScriptSetup s;
  s.backend = ChooseBackend(request.cli.backend, backends);
  s.factory = s.backend == BackendKind::kCuda ? backends.cudaSession : backends.cpuSession;
  s.options = MakeRenderOptions(request.cli, s.backend, nullptr);
  s.options.featureBuffers = request.featureBuffers || request.cli.denoise;  // denoise reads them
  s.options.timeLimitSeconds = 0.0;     // ScriptStop's
  s.options.previewEverySeconds = 0.0;  // refused as a keyword; never on here
  CheckChunkOptions(request.cli, scene, s.options, false);
  return s;
}

// denoise=True: image.denoised, and its time in the statistics (quietly: no stderr line).
void DenoiseScriptImage(Denoiser* denoiser, FilmImage& image, AppTimes* times) {
  if (!denoiser) return;
  denoiser->Denoise(image);
  times->denoiseMs = denoiser->LastMs();
}

uint64_t CropPixels(const Scene& scene, const RenderOptions& options) {
  const RenderSettings& r = scene.desc.render;
  CropWindow crop = options.crop.Empty() ? CropWindow{0, 0, r.width, r.height} : options.crop;
  return uint64_t(crop.x1 - crop.x0) * uint64_t(crop.y1 - crop.y0);
}

uint64_t SamplesIn(const FilmImage& image) {
  uint64_t total = 0;
  for (uint32_t c : image.samples) total += c;
  return total;
}

RunReport ScriptReport(const ScriptRequest& request, const ScriptScene& scene,
                       const Scene& built, const char* entry, const std::string& stopReason,
                       BackendKind backend) {
  RunReport r;
  r.commandLine.push_back(entry);
  for (const auto& [keyword, value] : request.keywords) r.commandLine.push_back(keyword + "=" + value);
  r.sceneFile = scene.Name();
  r.sppRequested = built.desc.render.spp;
  r.stopReason = stopReason;
  r.clampLuminance = request.cli.clampLuminance;
  r.deviceMemory = backend == BackendKind::kCuda;
  r.peakRssBytes = PeakRssBytes();
  return r;
}

}  // namespace

ScriptResult RenderScript(ScriptScene& scene, const ScriptRequest& request,
                          const AppBackends& backends) {
  ScriptRenderClock::time_point start = ScriptRenderClock::now();
  AppTimes times;
  const Scene& built = scene.Prepare(request.cli, &times);
  ScriptSetup setup = SetUpScriptRender(request, built, backends);
  ScriptStop stop(request.shouldStop, request.cli.timeLimitSeconds);
  RenderCallbacks callbacks;
  callbacks.shouldStop = [&stop] { return stop(); };
  RenderResult result;
  uint32_t chunks = uint32_t(request.cli.chunks.value_or(1));
  if (chunks > 1) {
    result = RenderChunked(setup.factory, built, setup.options, callbacks, chunks);
  } else {
    result = setup.factory(built, setup.options, callbacks)->Render();
  }
  std::unique_ptr<Denoiser> denoiser =
      MakeAppDenoiser(request.cli, built.desc.render.sampler, setup.backend, backends,
                      setup.options.device);
  DenoiseScriptImage(denoiser.get(), result.image, &times);
  ScriptResult out;
  out.stopped = stop.StoppedByUser();
  uint64_t wanted = CropPixels(built, setup.options) * uint64_t(built.desc.render.spp);
  std::string reason = out.stopped                          ? "signal"
                       : stop.TimeUp()                      ? "time_limit"
                       : SamplesIn(result.image) < wanted ? "converged"
                                                            : "completed";
  times.totalMs = MsFrom(start);
  RunReport report = ScriptReport(request, scene, built, "pathtracer.render", reason,
                                  setup.backend);
  out.stats = StatsToJson(result.stats, built, times, report);
  out.image = std::move(result.image);
  return out;
}

ProgressiveScript::ProgressiveScript(ScriptScene& scene, ScriptRequest request,
                                     const AppBackends& backends, std::vector<uint32_t> steps)
    : scene_(scene), request_(std::move(request)), start_(ScriptRenderClock::now()) {
  if (request_.cli.adaptive == Toggle::kOn) {
    throw CliError("--adaptive on does not go with render_progressive (every pixel takes the "
                   "same samples at each step)");
  }
  if (request_.cli.chunks.value_or(1) > 1) {
    throw CliError("--chunks does not go with render_progressive");
  }
  built_ = &scene_.Prepare(request_.cli, &times_);
  version_ = scene_.Version();
  ScriptSetup setup = SetUpScriptRender(request_, *built_, backends);
  setup.options.adaptive = Toggle::kOff;
  uint32_t spp = uint32_t(built_->desc.render.spp);
  if (steps.empty()) {
    for (uint32_t s = 1; s < spp; s *= 2) steps.push_back(s);
  }
  for (size_t i = 0; i < steps.size(); ++i) {
    if (steps[i] == 0 || steps[i] > spp || (i > 0 && steps[i] <= steps[i - 1])) {
      throw CliError("render_progressive steps must increase from 1 up to spp (" +
                     std::to_string(spp) + ")");
    }
  }
  if (steps.empty() || steps.back() < spp) steps.push_back(spp);
  steps_ = std::move(steps);
  backend_ = setup.backend;
  stop_ = std::make_unique<ScriptStop>(request_.shouldStop, request_.cli.timeLimitSeconds);
  RenderCallbacks callbacks;
  ScriptStop* stop = stop_.get();
  callbacks.shouldStop = [stop] { return (*stop)(); };
  pixels_ = CropPixels(*built_, setup.options);
  session_ = setup.factory(*built_, setup.options, callbacks);
  denoiser_ = MakeAppDenoiser(request_.cli, built_->desc.render.sampler, backend_, backends,
                              setup.options.device);
}

ProgressiveScript::~ProgressiveScript() = default;

bool ProgressiveScript::Next(ScriptResult* out) {
  if (ended_ || next_ >= steps_.size()) return false;
  if (scene_.Version() != version_) {
    throw std::logic_error("the scene was edited or rebuilt during render_progressive: start "
                           "a new one");
  }
  uint32_t to = steps_[next_++];
  uint64_t done = session_->RenderRange(spp_, to);
  bool complete = done == pixels_ * uint64_t(to - spp_);
  if (complete) spp_ = to;
  else ended_ = true;
  *out = ScriptResult{};
  out->stopped = stop_->StoppedByUser();
  out->image = session_->Image();
  AppTimes times = times_;
  DenoiseScriptImage(denoiser_.get(), out->image, &times);
  RenderStats stats = session_->Stats();
  stats.samples = SamplesIn(out->image);
  stats.sppMean = double(stats.samples) / double(std::max<uint64_t>(1, pixels_));
  std::string reason = out->stopped                   ? "signal"
                       : stop_->TimeUp()              ? "time_limit"
                       : next_ < steps_.size()      ? "in_progress"
                                                      : "completed";
  times.totalMs = MsFrom(start_);
  RunReport report = ScriptReport(request_, scene_, *built_, "pathtracer.render_progressive",
                                  reason, backend_);
  out->stats = StatsToJson(stats, *built_, times, report);
  return true;
}

}  // namespace pt
