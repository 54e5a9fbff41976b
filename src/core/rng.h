// Counter-based random numbers: every value is a pure function of (pixel, sample, bounce,
// dimension, seed), so a path draws the same numbers whichever thread, queue slot or backend
// runs it. That is what makes renders bit-identical across thread counts and flag settings.
#pragma once

#include "src/core/math.h"

namespace pt {

// pcg4d (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering"): 4 words in, 4 out.
PT_HDI glm::uvec4 Pcg4d(glm::uvec4 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  v ^= v >> 16u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  return v;
}

// 24 high bits to a float in [0, 1): exact, and never 1.0.
PT_HDI float BitsToUnitFloat(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

// Which random dimensions a bounce uses; each call of Draw4 yields four numbers.
enum RandomDim : uint32_t {
  kDimCamera = 0,       // pixel jitter (2) + lens (2)
  kDimLight = 1,        // light choice (1), light position (2), BVH walk (1)
  kDimBsdf = 2,         // lobe choice (1), direction (2), roulette (1)
  kDimsPerBounce = 4,
};

struct RngKey {
  uint32_t pixel, sample, seed;

  // Four uniform numbers for (bounce, dimension group).
  PT_HDI vec4 Draw4(uint32_t bounce, uint32_t dim) const {
    glm::uvec4 h = Pcg4d(glm::uvec4(pixel, sample, bounce * kDimsPerBounce + dim, seed));
    return vec4(BitsToUnitFloat(h.x), BitsToUnitFloat(h.y), BitsToUnitFloat(h.z),
                BitsToUnitFloat(h.w));
  }
};

}  // namespace pt
