// What `auto` means for --compact and --sort. Measured (benchmarks/RESULTS.md): compaction on
// and sorting off is the fastest fixed setting on every benchmark scene on the GPU, so `auto`
// is that everywhere; a per-scene choice would need a scene where the ranking changes.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

struct FlagChoice {
  bool compact;
  bool sort;
};

FlagChoice ChooseFlags(const RenderOptions& options);

}  // namespace pt
