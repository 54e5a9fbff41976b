#include "src/app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace pt {
namespace {

constexpr auto kMinInterval = std::chrono::milliseconds(100);  // <= 10 redraws per second
constexpr int kBarWidth = 30;

std::string FormatSeconds(double seconds) {
  char text[32];
  if (seconds < 60.0) std::snprintf(text, sizeof(text), "%.1fs", seconds);
  else std::snprintf(text, sizeof(text), "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  return text;
}

}  // namespace

ProgressBar::ProgressBar(bool quiet)
    : enabled_(!quiet && isatty(STDERR_FILENO)), start_(Clock::now()) {}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Update(uint64_t done, uint64_t total) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  Clock::time_point now = Clock::now();
  if (drawn_ && now - lastDraw_ < kMinInterval && done < total) return;
  lastDraw_ = now;
  Draw(done, total);
}

void ProgressBar::Draw(uint64_t done, uint64_t total) {
  double fraction = total ? std::clamp(double(done) / double(total), 0.0, 1.0) : 0.0;
  int filled = int(fraction * kBarWidth + 0.5);
  double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  std::string eta = fraction > 0.0 && fraction < 1.0
                        ? " eta " + FormatSeconds(elapsed * (1.0 - fraction) / fraction)
                        : "";
  std::string bar(size_t(filled), '#');
  bar.resize(kBarWidth, '.');
  // \r and erase-to-end so that a shorter line leaves no tail of the longer one.
  std::fprintf(stderr, "\r[%s] %5.1f%% %s%s\x1b[K", bar.c_str(), fraction * 100.0,
               FormatSeconds(elapsed).c_str(), eta.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::Finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (drawn_) {
    std::fprintf(stderr, "\r\x1b[K");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace pt
