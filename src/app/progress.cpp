#include "src/app/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace pt {
namespace {

constexpr auto kMinBarInterval = std::chrono::milliseconds(100);  // <= 10 redraws a second
constexpr int kBarWidth = 30;

std::string FormatSeconds(double seconds) {
  char text[32];
  if (seconds < 60.0) {
    std::snprintf(text, sizeof(text), "%.1fs", seconds);
  } else if (seconds < 3600.0) {
    std::snprintf(text, sizeof(text), "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof(text), "%dh%02dm", int(seconds) / 3600, int(seconds) % 3600 / 60);
  }
  return text;
}

double Fraction(const ProgressPoint& p) {
  return p.filmTarget ? std::clamp(double(p.filmSamples) / double(p.filmTarget), 0.0, 1.0) : 0.0;
}

// The time left at this run's rate, or "" before there is a rate.
std::string Eta(const ProgressPoint& p, double elapsed) {
  if (p.runSamples == 0 || elapsed <= 0.0 || p.filmSamples >= p.filmTarget) return "";
  double left = double(p.filmTarget - p.filmSamples) / (double(p.runSamples) / elapsed);
  return FormatSeconds(left);
}

}  // namespace

ProgressReporter::ProgressReporter(bool quiet, double lineEverySeconds)
    : ProgressReporter(quiet ? Mode::kOff : isatty(STDERR_FILENO) ? Mode::kBar : Mode::kLines,
                       lineEverySeconds) {}

ProgressReporter::ProgressReporter(Mode mode, double lineEverySeconds)
    : mode_(mode), lineEverySeconds_(lineEverySeconds), start_(Clock::now()), last_(start_) {}

ProgressReporter::~ProgressReporter() { Finish(); }

std::string ProgressReporter::Line(const ProgressPoint& p, double elapsed) {
  double pixels = double(std::max<uint64_t>(p.pixels, 1));
  double rate = elapsed > 0.0 ? double(p.runSamples) / elapsed / 1e6 : 0.0;
  std::string eta = Eta(p, elapsed);
  char text[200];
  std::snprintf(text, sizeof(text), "%.1f of %.0f spp (%.1f%%), %.2f Msamples/s, %s elapsed%s%s",
                double(p.filmSamples) / pixels, double(p.filmTarget) / pixels,
                Fraction(p) * 100.0, rate, FormatSeconds(elapsed).c_str(),
                eta.empty() ? "" : ", eta ", eta.c_str());
  return text;
}

void ProgressReporter::Update(const ProgressPoint& point) {
  if (mode_ == Mode::kOff) return;
  std::lock_guard<std::mutex> lock(mutex_);
  Clock::time_point now = Clock::now();
  if (mode_ == Mode::kBar) {
    if (drawn_ && now - last_ < kMinBarInterval && point.filmSamples < point.filmTarget) return;
    last_ = now;
    DrawBar(point);
    return;
  }
  if (std::chrono::duration<double>(now - last_).count() < lineEverySeconds_) return;
  last_ = now;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "pathtracer: %s\n", Line(point, elapsed).c_str());
  std::fflush(stderr);
}

void ProgressReporter::Note(const std::string& line) {
  if (mode_ != Mode::kLines) return;
  std::lock_guard<std::mutex> lock(mutex_);
  std::fprintf(stderr, "pathtracer: %s\n", line.c_str());
  std::fflush(stderr);
}

void ProgressReporter::DrawBar(const ProgressPoint& point) {
  double fraction = Fraction(point);
  int filled = int(fraction * kBarWidth + 0.5);
  double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  std::string eta = Eta(point, elapsed);
  std::string bar(size_t(filled), '#');
  bar.resize(kBarWidth, '.');
  // \r and erase-to-end so that a shorter line leaves no tail of the longer one.
  std::fprintf(stderr, "\r[%s] %5.1f%% %s%s%s\x1b[K", bar.c_str(), fraction * 100.0,
               FormatSeconds(elapsed).c_str(), eta.empty() ? "" : " eta ", eta.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressReporter::Finish() {
  if (mode_ != Mode::kBar) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (drawn_) {
    std::fprintf(stderr, "\r\x1b[K");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace pt
