// A progress bar on stderr, drawn only when stderr is a terminal and --quiet is not given,
// and at most ten times a second so that it never slows the render.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>

namespace pt {

class ProgressBar {
 public:
  // quiet: --quiet. The bar also stays off when stderr is not a terminal.
  explicit ProgressBar(bool quiet);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  bool Enabled() const { return enabled_; }
  // Safe to call from any thread, as often as the renderer likes.
  void Update(uint64_t done, uint64_t total);
  // Clears the bar's line so that the next message starts clean.
  void Finish();

 private:
  using Clock = std::chrono::steady_clock;
  void Draw(uint64_t done, uint64_t total);

  bool enabled_ = false;
  bool drawn_ = false;
  std::mutex mutex_;
  Clock::time_point start_;
  Clock::time_point lastDraw_;
};

}  // namespace pt
