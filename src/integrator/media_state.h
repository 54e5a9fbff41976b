// The path state only scenes with participating media allocate (src/integrator/media_pass.h).
#pragma once

#include "src/core/math.h"

namespace pt {

// The path state only scenes with media allocate. Media are stored as index + 1 (0: vacuum).
struct MediaState {
  uint32_t* medium;        // the medium the path's current ray travels in
  uint32_t* shadowMedium;  // the medium the queued shadow ray starts in
  vec3* rHat;              // the path's rescaled channel probabilities, average 1
};
constexpr size_t kMediaStateBytes = 2 * sizeof(uint32_t) + sizeof(vec3);

}  // namespace pt
