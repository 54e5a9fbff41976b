// The named wavefront stages, for per-stage timing on every backend.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

// kShadeQueue + q: the shade kernel of queue q (--sort queues), timed as shading and per queue.
enum class Stage : uint32_t {
  kGenerate, kIntersect, kSort, kShade, kShadow, kCompact, kAccumulate,
  kMedium,  // scenes with participating media only (stages/medium.h)
  kShadeQueue
};

inline Stage ShadeQueueStage(uint32_t q) { return Stage(uint32_t(Stage::kShadeQueue) + q); }

inline void AddStageTime(StageTimes& t, Stage s, double ms) {
  switch (s) {
    case Stage::kGenerate: t.generate += ms; break;
    case Stage::kIntersect: t.intersect += ms; break;
    case Stage::kSort: t.sort += ms; break;
    case Stage::kShade: t.shade += ms; break;
    case Stage::kShadow: t.shadow += ms; break;
    case Stage::kCompact: t.compact += ms; break;
    case Stage::kAccumulate: t.accumulate += ms; break;
    case Stage::kMedium: t.medium += ms; break;
    default: {
      uint32_t q = uint32_t(s) - uint32_t(Stage::kShadeQueue);
      t.shade += ms;
      if (q < kShadeQueueCount) t.shadeQueues[q] += ms;
      break;
    }
  }
}

}  // namespace pt
