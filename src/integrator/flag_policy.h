// What `auto` means for --compact (--sort's auto is ChooseSortMode in shade_order.h: it reads
// the scene's materials). Measured (benchmarks/RESULTS.md): compaction on is the fastest fixed
// setting on every benchmark scene on the GPU, so `auto` is that everywhere.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

struct FlagChoice {
  bool compact;
};

FlagChoice ChooseFlags(const RenderOptions& options);

// --ray-order: whether each bounce's rays are sorted before intersect (stages/ray_order.h).
// lockstep: the backend runs neighbouring paths together (GPU warps); prims: the scene's count
// (of placed primitives, for a scene with instances).
bool ChooseRayOrder(Toggle asked, bool lockstep, size_t prims);

// --prim-pool: whether a warp's lanes test the primitives of their leaves together
// (geometry/traverse_wide_pooled.h). It exists for the wide layout of a flat scene on a backend
// whose lanes run in lockstep; wideFlat: the scene is one. prims as for ChooseRayOrder.
bool ChoosePrimPool(Toggle asked, bool lockstep, bool wideFlat, size_t prims);

}  // namespace pt
