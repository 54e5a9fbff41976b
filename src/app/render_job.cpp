#include "src/app/render_job.h"

#include <chrono>
#include <cstdio>
#include <optional>

#include "src/app/app_failure.h"
#include "src/app/progress.h"
#include "src/app/stop_signals.h"
#include "src/distributed/chunked_render.h"
#include "src/integrator/wave_plan.h"
#include "src/io/image_io.h"

namespace pt {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

uint64_t FilmSamples(const std::vector<uint32_t>& counts) {
  uint64_t total = 0;
  for (uint32_t c : counts) total += c;
  return total;
}

// Previews (-o, --hdr, --spp-map every --preview-every seconds) and checkpoints (--hdr as a
// resumable state every --checkpoint-every seconds), written between waves.
class PeriodicWriter {
 public:
  PeriodicWriter(const RenderJob& job, ProgressReporter& progress)
      : cli_(*job.cli), job_(job), progress_(progress) {}

  int Checkpoints() const { return checkpoints_; }

  void AfterWave(RenderSession& session) {
    bool preview = Due(cli_.previewEverySeconds, lastPreview_);
    bool checkpoint = Due(cli_.checkpointEverySeconds, lastCheckpoint_);
    if (!preview && !checkpoint) return;
    try {
      if (cli_.checkpointEverySeconds <= 0.0) {
        FilmImage image = session.Image();
        if (job_.denoiser) job_.denoiser->Denoise(image);
        WriteImages(cli_, image, nullptr);
        return;
      }
      // With checkpoints on, every --hdr written is resumable (a preview included).
      FilmState film = session.SaveFilm();
      FilmImage image = ResolveFilmImage(film);
      if (preview && job_.denoiser) job_.denoiser->Denoise(image);
      ResumableState state{&film, job_.options.filmDouble, job_.description};
      if (preview) WriteImages(cli_, image, &state);
      else WriteCheckpoint(cli_, image, state);
      ++checkpoints_;
      char note[200];
      std::snprintf(note, sizeof(note), "checkpoint %d written to %s (%.1f spp)", checkpoints_,
                    cli_.hdrPath.c_str(), double(FilmSamples(film.count)) / film.PixelCount());
      progress_.Note(note);
    } catch (const ImageError& e) {  // the final write reports it for good
      std::fprintf(stderr, "\npathtracer: warning: %s not written: %s\n",
                   checkpoint ? "checkpoint" : "preview", e.what());
    }
  }

 private:
  static bool Due(double every, Clock::time_point& last) {
    if (every <= 0.0 || SecondsSince(last) < every) return false;
    last = Clock::now();
    return true;
  }

  const CliOptions& cli_;
  const RenderJob& job_;
  ProgressReporter& progress_;
  Clock::time_point lastPreview_ = Clock::now(), lastCheckpoint_ = Clock::now();
  int checkpoints_ = 0;
};

// --time-limit, measured from the first wave (after scene upload), and the stop signals.
class StopCheck {
 public:
  explicit StopCheck(double limitSeconds) : limit_(limitSeconds) {}
  bool operator()() {
    if (StopSignal() != 0) return true;
    if (!start_) start_ = Clock::now();
    if (limit_ > 0.0 && SecondsSince(*start_) >= limit_) timeUp_ = true;
    return timeUp_;
  }
  bool TimeUp() const { return timeUp_; }

 private:
  double limit_;
  std::optional<Clock::time_point> start_;
  bool timeUp_ = false;
};

void Resume(RenderSession& session, const FilmState& film, const std::string& path) {
  try {
    session.LoadFilm(film);
  } catch (const std::invalid_argument& e) {
    throw AppFailure{kExitBadInput, path + ": cannot resume: " + e.what()};
  }
}

}  // namespace

const char* StopReasonName(StopReason reason) {
  switch (reason) {
    case StopReason::kTimeLimit: return "time_limit";
    case StopReason::kSignal: return "signal";
    case StopReason::kConverged: return "converged";
    case StopReason::kFailed: return "failed";
    default: return "completed";
  }
}

JobOutcome RunRenderJob(const RenderJob& job) {
  const CliOptions& cli = *job.cli;
  const RenderSettings& settings = job.scene->desc.render;
  CropWindow crop = job.options.crop.Empty()
                        ? CropWindow{0, 0, settings.width, settings.height}
                        : job.options.crop;
  uint64_t pixels = uint64_t(crop.x1 - crop.x0) * uint64_t(crop.y1 - crop.y0);
  JobOutcome out;
  out.resumedSamples = job.resumeFrom ? FilmSamples(job.resumeFrom->count) : 0;

  ProgressReporter progress(cli.quiet, cli.progressEverySeconds);
  PeriodicWriter writer(job, progress);
  StopCheck stop(cli.timeLimitSeconds);
  RenderSession* session = nullptr;
  RenderCallbacks callbacks;
  callbacks.shouldStop = [&stop] { return stop(); };
  callbacks.onProgress = [&](uint64_t done, uint64_t) {
    if (!out.firstPixel) out.firstPixel = Clock::now();
    progress.Update({done, out.resumedSamples + done, pixels * uint64_t(settings.spp), pixels});
    if (session) writer.AfterWave(*session);  // none with --chunks (no previews then)
  };
  RenderOptions options = job.options;
  options.timeLimitSeconds = 0.0;     // StopCheck's, which knows it was the time limit
  options.previewEverySeconds = 0.0;  // PeriodicWriter's, which keeps --hdr resumable
  std::unique_ptr<RenderSession> owned;
  if (job.chunks > 1) {
    out.result = RenderChunked(job.makeSession, *job.scene, options, callbacks, job.chunks);
  } else {
    const Clock::time_point made = Clock::now();
    owned = job.makeSession(*job.scene, options, callbacks);
    out.sessionMs = SecondsSince(made) * 1e3;
    session = owned.get();
    if (job.resumeFrom) Resume(*session, *job.resumeFrom, cli.resumePath);
    out.result = session->Render();
  }
  progress.Finish();
  out.checkpoints = writer.Checkpoints();
  out.signal = StopSignal();
  uint64_t filmSamples = FilmSamples(out.result.image.samples);
  if (out.signal != 0) out.reason = StopReason::kSignal;
  else if (stop.TimeUp()) out.reason = StopReason::kTimeLimit;
  else if (filmSamples < pixels * uint64_t(settings.spp)) out.reason = StopReason::kConverged;
  out.keepState = session && IsExrPath(cli.hdrPath) &&
                  (cli.checkpointEverySeconds > 0.0 || out.reason == StopReason::kSignal ||
                   out.reason == StopReason::kTimeLimit);
  if (out.keepState) out.film = session->SaveFilm();
  const Clock::time_point freed = Clock::now();
  owned.reset();
  out.teardownMs = SecondsSince(freed) * 1e3;
  return out;
}

}  // namespace pt
