// What `auto` means for --compact and --sort, per backend and scene.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

struct FlagChoice {
  bool compact;
  bool sort;
};

FlagChoice ChooseFlags(const Scene& scene, const RenderOptions& options, bool gpu);

}  // namespace pt
