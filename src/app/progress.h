// Render progress on stderr: a bar redrawn in place when stderr is a terminal (at most ten
// times a second), else one line every few seconds for logs (spp, percentage, rate, ETA).
// --quiet turns both off.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace pt {

// Where a render stands: samples this run took, and the film's samples against its target
// (a resumed render starts with samples in the film).
struct ProgressPoint {
  uint64_t runSamples = 0;
  uint64_t filmSamples = 0, filmTarget = 0;
  uint64_t pixels = 1;
};

class ProgressReporter {
 public:
  enum class Mode { kOff, kBar, kLines };

  // quiet: --quiet; lineEverySeconds: the interval of progress lines (--progress-every).
  ProgressReporter(bool quiet, double lineEverySeconds);
  ProgressReporter(Mode mode, double lineEverySeconds);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  Mode GetMode() const { return mode_; }
  // Safe to call from any thread, as often as the renderer likes.
  void Update(const ProgressPoint& point);
  // A message line between progress output (lines mode only; the bar stays clean).
  void Note(const std::string& line);
  // Clears the bar's line so that the next message starts clean.
  void Finish();

  // The progress line's text (without "pathtracer: "), for lines mode and for tests.
  static std::string Line(const ProgressPoint& point, double elapsedSeconds);

 private:
  using Clock = std::chrono::steady_clock;
  void DrawBar(const ProgressPoint& point);

  Mode mode_ = Mode::kOff;
  double lineEverySeconds_ = 10.0;
  bool drawn_ = false;
  std::mutex mutex_;
  Clock::time_point start_;
  Clock::time_point last_;
};

}  // namespace pt
