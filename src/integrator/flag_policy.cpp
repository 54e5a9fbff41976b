#include "src/integrator/flag_policy.h"

namespace pt {

FlagChoice ChooseFlags(const RenderOptions& options) {
  // Compaction: dead lanes waste whole GPU warps, and on the CPU the pass over 4-byte indices
  // costs less than visiting dead slots in every later stage.
  bool compact = options.compact != Toggle::kOff;
  // Sorting pays only with many materials of very different cost: on the benchmark scenes the
  // radix sort per bounce costs more than the divergence it removes (1.03-1.7x slower).
  bool sort = options.sort == SortMode::kMaterial;
  return FlagChoice{compact, sort};
}

}  // namespace pt
