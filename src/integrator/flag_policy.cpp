#include "src/integrator/flag_policy.h"

namespace pt {

FlagChoice ChooseFlags(const RenderOptions& options) {
  // Compaction: dead lanes waste whole GPU warps, and on the CPU the pass over 4-byte indices
  // costs less than visiting dead slots in every later stage.
  bool compact = options.compact != Toggle::kOff;
  return FlagChoice{compact};
}

// Sorting costs a pass over the rays and scatters the traced path state: it pays where the
// traversal is long (large scenes) and only where rays run in lockstep. Measured on an H100
// (benchmarks/RESULTS.md): a win on the Breakfast Room (270k triangles) and its 3.3M-triangle
// variant, a loss on the bunny Cornell (69k) and pbrt's box.
constexpr size_t kRayOrderMinPrims = size_t(1) << 17;

bool ChooseRayOrder(Toggle asked, bool lockstep, size_t prims) {
  if (asked != Toggle::kAuto) return asked == Toggle::kOn;
  return lockstep && prims >= kRayOrderMinPrims;
}

// Pooling pays where walks are long (measured on an H200, benchmarks/RESULTS.md, 2026-11-26:
// 1.16-1.18x per render on the Breakfast Room and its 3.3M-triangle variant) and costs 3-11% on
// the bunny Cornell and pbrt's box, so auto uses ray ordering's threshold.
bool ChoosePrimPool(Toggle asked, bool lockstep, bool wideFlat, size_t prims) {
  if (!lockstep || !wideFlat || asked == Toggle::kOff) return false;
  return asked == Toggle::kOn || prims >= kRayOrderMinPrims;
}

}  // namespace pt
