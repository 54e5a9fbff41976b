#include "src/integrator/flag_policy.h"

namespace pt {

FlagChoice ChooseFlags(const RenderOptions& options) {
  // Compaction: dead lanes waste whole GPU warps, and on the CPU the pass over 4-byte indices
  // costs less than visiting dead slots in every later stage.
  bool compact = options.compact != Toggle::kOff;
  return FlagChoice{compact};
}

bool ChooseRayOrder(Toggle asked, bool lockstep, size_t prims) {
  if (asked != Toggle::kAuto) return asked == Toggle::kOn;
  (void)lockstep;
  (void)prims;
  return false;  // measured in benchmarks/RESULTS.md before it is turned on anywhere
}

}  // namespace pt
