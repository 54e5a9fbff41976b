// One render as the app runs it: a RenderSession (resumed from a film when asked), stopped by
// a signal or --time-limit between waves, with progress, previews and checkpoints written as
// it goes, and the reason it stopped.
#pragma once

#include <chrono>
#include <optional>
#include <string>

#include "src/app/cli.h"
#include "src/app/outputs.h"
#include "src/app/run.h"

namespace pt {

// kFailed: an MPI job ended early by a rank that failed or stopped answering.
enum class StopReason { kCompleted, kTimeLimit, kSignal, kConverged, kFailed };
const char* StopReasonName(StopReason reason);  // "completed", "time_limit", ...

struct RenderJob {
  const CliOptions* cli = nullptr;
  const Scene* scene = nullptr;
  SessionFactory makeSession = nullptr;
  RenderOptions options;                // as the command line asks
  const FilmState* resumeFrom = nullptr;  // --resume's film, or null
  std::string description;              // the render's, for resumable states (resume.h)
  // > 1: the samples cut into this many chunks merged along a fixed tree (--chunks: the image
  // of an MPI job with the same chunks); no resumable state then.
  uint32_t chunks = 1;
  Denoiser* denoiser = nullptr;  // --denoise: previews are denoised too (the result by the app)
};

struct JobOutcome {
  RenderResult result;   // the film's image; stats.samples counts this run's samples only
  // Where the job's time went beside the session's upload and render (stats): making the
  // session (the device's start-up), and freeing it; when the first wave's samples were in.
  double sessionMs = 0.0, teardownMs = 0.0;
  std::optional<std::chrono::steady_clock::time_point> firstPixel;
  StopReason reason = StopReason::kCompleted;
  int signal = 0;        // the stop signal, when reason is kSignal
  uint64_t resumedSamples = 0;
  int checkpoints = 0;
  // The film, kept when the --hdr EXR is to be resumable: --checkpoint-every was given, or the
  // render stopped before its samples were done.
  bool keepState = false;
  FilmState film;
};

// Throws AppFailure (exit 2) when the resumed film does not fit this render.
JobOutcome RunRenderJob(const RenderJob& job);

}  // namespace pt
