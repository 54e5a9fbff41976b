// The run's wall time cut into named, consecutive parts on the main thread (issue 28: "every
// millisecond named"): the first part is the process's start before main() (exec, the dynamic
// loader, static initialisers), each Mark closes the part since the previous one, and Split
// cuts a part into pieces measured inside it. The parts sum to the time from the process's
// start to the last mark, which --stats-json reports as time_ms.total.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pt {

class RunTimeline {
 public:
  using Clock = std::chrono::steady_clock;

  // mainStart: when main() began; the part before it is named firstPart ("process_start", or
  // "launch" for an MPI rank, which then has MPI_Init in it too: Mark it once initialised).
  explicit RunTimeline(Clock::time_point mainStart, std::string firstPart = "process_start");

  // The time since the previous mark (or main's start) becomes `part` (added to it when the
  // name is already there).
  void Mark(const std::string& part);
  // Replaces the last part named `part` with `pieces` (measured inside it, in order) and
  // `rest` (what is left, at least 0).
  void Split(const std::string& part, const std::vector<std::pair<std::string, double>>& pieces,
             const std::string& rest);
  // A moment to report as milliseconds since the process's start (time to first pixel).
  void SetFirstPixel(Clock::time_point t) { firstPixel_ = t; }

  // The parts in run order, a name once (repeated names summed).
  std::vector<std::pair<std::string, double>> Parts() const;
  double Part(const std::string& name) const;  // 0 when absent
  double TotalMs() const;                      // the parts' sum
  std::optional<double> FirstPixelMs() const;

  // Milliseconds from the process's start to main(), as the kernel recorded the start (in
  // clock ticks, 10 ms on Linux: hence measured, not estimated); 0 where unknown.
  static double BeforeMainMs(Clock::time_point mainStart);

 private:
  Clock::time_point processStart_, last_;
  std::vector<std::pair<std::string, double>> parts_;
  std::optional<Clock::time_point> firstPixel_;
};

}  // namespace pt
