// The named wavefront stages, for per-stage timing on every backend.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

enum class Stage { kGenerate, kIntersect, kSort, kShade, kShadow, kCompact, kAccumulate, kCount };

inline double& StageTime(StageTimes& t, Stage s) {
  switch (s) {
    case Stage::kGenerate: return t.generate;
    case Stage::kIntersect: return t.intersect;
    case Stage::kSort: return t.sort;
    case Stage::kShade: return t.shade;
    case Stage::kShadow: return t.shadow;
    case Stage::kCompact: return t.compact;
    case Stage::kAccumulate:
    default: return t.accumulate;
  }
}

}  // namespace pt
