#include "src/integrator/flag_policy.h"

namespace pt {

FlagChoice ChooseFlags(const Scene& scene, const RenderOptions& options, bool gpu) {
  // Compaction: on the CPU a dead slot costs a branch and compaction a cheap pass, and on the
  // GPU dead lanes waste whole warps; both benefit once paths start to die.
  bool compact = options.compact != Toggle::kOff;
  // Sorting buys coherence only where warps execute in lockstep and materials differ in
  // cost; with one or two material types it cannot pay for itself.
  bool sort = options.sort == SortMode::kMaterial;
  (void)scene;
  (void)gpu;
  return FlagChoice{compact, sort};
}

}  // namespace pt
