// Counter-based random numbers: every value is a pure function of (pixel, sample, bounce,
// dimension, seed), so a path draws the same numbers whichever thread, queue slot or backend
// runs it. That is what makes renders bit-identical across thread counts and flag settings.
#pragma once

#include "src/core/math.h"
#include "src/core/sobol_burley.h"

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

// Where Draw4's numbers come from (--sampler; docs/sampling.md): independent uniform numbers
// (pcg4d), or Owen-scrambled Sobol pairs (sobol_burley.h), stratified over a pixel's samples.
// kSobolHalves is what kSobol becomes for a film that keeps two half films (--denoise): the
// even and the odd samples are two independently scrambled Sobol sequences (replicates), each
// indexed by sample / 2, so the halves' difference measures their noise (one sequence's halves
// cancel each other's errors, which the denoiser cannot see; docs/denoise.md). The integrator
// chooses it; it is never asked for by name.
enum class SamplerKind : uint32_t { kIndependent = 0, kSobol = 1, kSobolHalves = 2 };

inline const char* SamplerKindName(SamplerKind s) {
  return s == SamplerKind::kIndependent ? "independent" : "sobol";
}

// Padded Sobol: group `dim` of `bounce` as two Owen-scrambled Sobol pairs, each seeded by a
// hash of (pixel, bounce, dim, pair, seed) and indexed by the pixel's sample. Pair 0 is the
// group's 2D domain, where stratification pays: the pixel jitter (x, y), or the light
// position and the BSDF direction (y, z); pair 1 takes the rest (lens; light choice and BVH
// walk; lobe choice and roulette).
PT_HDI vec4 DrawSobol4(uint32_t pixel, uint32_t sample, uint32_t seed, uint32_t bounce,
                       uint32_t dim) {
  constexpr uint32_t kPairSalt = 0x50424f53u;  // keeps the pairs' hashes off pcg4d's inputs
  const uint32_t group = bounce * kDimsPerBounce + dim;
  glm::uvec4 h0 = Pcg4d(glm::uvec4(pixel, group, seed, kPairSalt));
  glm::uvec4 h1 = Pcg4d(glm::uvec4(pixel, group, seed, kPairSalt + 1u));
  glm::uvec2 a = SobolBurleyPair(sample, glm::uvec3(h0));
  glm::uvec2 b = SobolBurleyPair(sample, glm::uvec3(h1));
  vec2 fa(BitsToUnitFloat(a.x), BitsToUnitFloat(a.y));
  vec2 fb(BitsToUnitFloat(b.x), BitsToUnitFloat(b.y));
  return dim == kDimCamera ? vec4(fa, fb) : vec4(fb.x, fa.x, fa.y, fb.y);
}

struct RngKey {
  uint32_t pixel, sample, seed;
  SamplerKind sampler = SamplerKind::kIndependent;

  // Four uniform numbers for (bounce, dimension group). The sampler is the same for every
  // path of a render: a uniform branch.
  PT_HDI vec4 Draw4(uint32_t bounce, uint32_t dim) const {
    if (sampler != SamplerKind::kIndependent) {
      bool halves = sampler == SamplerKind::kSobolHalves;
      uint32_t replicate = halves ? 0x9e3779b9u * ((sample & 1u) + 1u) : 0u;
      return DrawSobol4(pixel, halves ? sample >> 1 : sample, seed ^ replicate, bounce, dim);
    }
    glm::uvec4 h = Pcg4d(glm::uvec4(pixel, sample, bounce * kDimsPerBounce + dim, seed));
    return vec4(BitsToUnitFloat(h.x), BitsToUnitFloat(h.y), BitsToUnitFloat(h.z),
                BitsToUnitFloat(h.w));
  }
};

}  // namespace pt
