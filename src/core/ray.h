// Rays and the robust spawning of new rays from surfaces (error-bound offsets, as pbrt-v4),
// so no result depends on a fixed epsilon or on the scene's scale.
#pragma once

#include "src/core/math.h"

namespace pt {

struct Ray {
  vec3 o;
  vec3 d;
};

// Pushes p just past the error box pError along the geometric normal n, onto the side w points
// to, then rounds each coordinate away from the surface.
PT_HDI vec3 OffsetRayOrigin(vec3 p, vec3 pError, vec3 n, vec3 w) {
  float d = glm::dot(Abs(n), pError);
  vec3 offset = d * n;
  if (glm::dot(w, n) < 0.0f) offset = -offset;
  vec3 po = p + offset;
  for (int i = 0; i < 3; ++i) {
    if (offset[i] > 0.0f) po[i] = NextFloatUp(po[i]);
    else if (offset[i] < 0.0f) po[i] = NextFloatDown(po[i]);
  }
  return po;
}

// A global fixed-epsilon alternative exists only for the robustness study (--ray-offset EPS,
// a later issue); the renderer always uses OffsetRayOrigin.

}  // namespace pt
