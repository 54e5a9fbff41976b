#include "src/app/run_timeline.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

namespace pt {
namespace {

double Ms(RunTimeline::Clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

// The process's start in seconds since boot: field 22 of /proc/self/stat, in clock ticks.
bool ProcessStartSinceBoot(double* seconds) {
  FILE* f = std::fopen("/proc/self/stat", "r");
  if (!f) return false;
  char buf[1024];
  size_t n = std::fread(buf, 1, sizeof(buf) - 1, f);
  std::fclose(f);
  buf[n] = '\0';
  // The command name (field 2) may hold spaces and parentheses: count from the last ')'.
  const char* p = std::strrchr(buf, ')');
  if (!p) return false;
  unsigned long long start = 0;
  int field = 2;
  for (const char* s = p + 1; *s && field < 22; ++s) {
    if (*s == ' ') {
      ++field;
      if (field == 22 && std::sscanf(s + 1, "%llu", &start) != 1) return false;
    }
  }
  const long ticks = sysconf(_SC_CLK_TCK);
  if (field != 22 || ticks <= 0) return false;
  // The kernel truncates to a tick: the middle of it is within half a tick of the truth.
  *seconds = (double(start) + 0.5) / double(ticks);
  return true;
}

}  // namespace

double RunTimeline::BeforeMainMs(Clock::time_point mainStart) {
  double startSeconds = 0.0;
  timespec boot{};
  if (!ProcessStartSinceBoot(&startSeconds) || clock_gettime(CLOCK_BOOTTIME, &boot) != 0)
    return 0.0;
  const double sinceStart = double(boot.tv_sec) + 1e-9 * double(boot.tv_nsec) - startSeconds;
  const double sinceMain = Ms(Clock::now() - mainStart) * 1e-3;
  return std::clamp(1e3 * (sinceStart - sinceMain), 0.0, 60e3);
}

RunTimeline::RunTimeline(Clock::time_point mainStart, std::string firstPart)
    : last_(mainStart) {
  const double before = BeforeMainMs(mainStart);
  processStart_ = mainStart - std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double, std::milli>(before));
  parts_.emplace_back(std::move(firstPart), before);
}

void RunTimeline::Mark(const std::string& part) {
  const Clock::time_point now = Clock::now();
  parts_.emplace_back(part, Ms(now - last_));
  last_ = now;
}

void RunTimeline::Split(const std::string& part,
                        const std::vector<std::pair<std::string, double>>& pieces,
                        const std::string& rest) {
  for (size_t i = parts_.size(); i-- > 0;) {
    if (parts_[i].first != part) continue;
    double left = parts_[i].second;
    std::vector<std::pair<std::string, double>> cut;
    for (const auto& [name, ms] : pieces) {
      const double take = std::clamp(ms, 0.0, left);
      cut.emplace_back(name, take);
      left -= take;
    }
    cut.emplace_back(rest, left);
    parts_.erase(parts_.begin() + long(i));
    parts_.insert(parts_.begin() + long(i), cut.begin(), cut.end());
    return;
  }
}

std::vector<std::pair<std::string, double>> RunTimeline::Parts() const {
  std::vector<std::pair<std::string, double>> merged;
  for (const auto& [name, ms] : parts_) {
    auto it = std::find_if(merged.begin(), merged.end(),
                           [&](const auto& p) { return p.first == name; });
    if (it == merged.end()) merged.emplace_back(name, ms);
    else it->second += ms;
  }
  return merged;
}

double RunTimeline::Part(const std::string& name) const {
  double sum = 0.0;
  for (const auto& [n, ms] : parts_) sum += n == name ? ms : 0.0;
  return sum;
}

double RunTimeline::TotalMs() const {
  double sum = 0.0;
  for (const auto& p : parts_) sum += p.second;
  return sum;
}

std::optional<double> RunTimeline::FirstPixelMs() const {
  if (!firstPixel_) return std::nullopt;
  return Ms(*firstPixel_ - processStart_);
}

}  // namespace pt
