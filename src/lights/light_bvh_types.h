// The light BVH's device data (src/lights/light_bvh.h walks it, light_bvh_build.cpp builds it)
// and the choice of light sampler. Plain structs, so SceneView can hold them.
#pragma once

#include "src/core/math.h"

namespace pt {

// How next-event estimation chooses a light (--light-sampler). kUniform: every light alike;
// kPower: by power (the table SceneView::lightPmf); kBvh: lights at infinity by power, as
// kPower does, and the others through the light BVH by their importance at the shading point.
// kAuto is resolved on the host (ChooseLightSampler) and never reaches a stage.
enum class LightSampler : uint32_t { kUniform = 0, kPower = 1, kBvh = 2, kAuto = 3 };

// 32 bytes: a node of the light BVH, two siblings per 64-byte line. Bounds on a 16-bit grid
// over the tree's box (LightTreeView::lo, scale), rounded outwards; the orientation cone's
// axis as an octahedral unit vector, its cosines quantised downwards (wider cones), so every
// decoded node bounds what its lights emit. Interior: children `child` and `child + 1`; leaf:
// `child` = kLeafBit | the light's index in SceneView::lights.
struct alignas(16) LightBvhNode {
  float phi;          // summed intensity scale of the lights below (LightBoundsOf)
  uint32_t child;
  uint32_t axis;      // octahedral, x in the low 16 bits
  // cos theta_o: bits 0-14, cos theta_e: bits 15-29, bit 30: two-sided, bit 31: flat (every
  // light below is a one-sided flat emitter of normal exactly `axis`, before its rounding)
  uint32_t cosines;
  uint16_t qlo[3], qhi[3];
  uint32_t pad;

  static constexpr uint32_t kLeafBit = 1u << 31;
  PT_HDI bool IsLeaf() const { return (child & kLeafBit) != 0; }
  PT_HDI uint32_t Light() const { return child & ~kLeafBit; }
};
static_assert(sizeof(LightBvhNode) == 32, "light BVH node is meant to be 32 bytes");

// What the light stages read besides the arrays: the sampler in use (session state, set by
// the integrator from RenderOptions) and the tree's quantisation grid.
struct LightTreeView {
  uint32_t sampler = uint32_t(LightSampler::kPower);
  uint32_t nodeCount = 0;     // 0: no tree (no finite light with power)
  uint32_t boundedCount = 0;  // lights [0, boundedCount) are finite (area, point, spot)
  vec3 lo = vec3(0.0f);       // the grid: lo + q * scale
  vec3 scale = vec3(0.0f);
};

// Depth limit of the tree: a light's path from the root fits a 64-bit trail with its
// end marker (SceneView::lightTrails).
constexpr int kLightBvhMaxDepth = 62;

// ---- Encodings shared by the builder and the traversal ----

PT_HDI float SignNotZero(float v) { return v < 0.0f ? -1.0f : 1.0f; }

// A unit vector as two 16-bit octahedral coordinates (x low, y high).
PT_HDI uint32_t EncodeOctahedral(vec3 v) {
  float l1 = fabsf(v.x) + fabsf(v.y) + fabsf(v.z);
  if (!(l1 > 0.0f)) return 0x7fff7fffu;  // the zero vector: the octahedron's centre
  float x = v.x / l1, y = v.y / l1;
  if (v.z < 0.0f) {
    float ox = (1.0f - fabsf(y)) * SignNotZero(x);
    y = (1.0f - fabsf(x)) * SignNotZero(y);
    x = ox;
  }
  auto quantise = [](float c) {
    float q = floorf((fminf(fmaxf(c, -1.0f), 1.0f) * 0.5f + 0.5f) * 65535.0f + 0.5f);
    return uint32_t(q);
  };
  return quantise(x) | (quantise(y) << 16);
}

PT_HDI vec3 DecodeOctahedral(uint32_t e) {
  float x = float(e & 0xffffu) * (2.0f / 65535.0f) - 1.0f;
  float y = float(e >> 16) * (2.0f / 65535.0f) - 1.0f;
  vec3 v(x, y, 1.0f - fabsf(x) - fabsf(y));
  if (v.z < 0.0f) {
    float ox = (1.0f - fabsf(y)) * SignNotZero(x);
    v.y = (1.0f - fabsf(x)) * SignNotZero(y);
    v.x = ox;
  }
  return glm::normalize(v);
}

// A cosine in [-1, 1] as 15 bits, rounded down (a decoded cone is never narrower).
constexpr uint32_t kCosineSteps = (1u << 15) - 1u;
PT_HDI uint32_t QuantiseCosDown(float c) {
  float q = floorf((fminf(fmaxf(c, -1.0f), 1.0f) * 0.5f + 0.5f) * float(kCosineSteps));
  return uint32_t(fminf(fmaxf(q, 0.0f), float(kCosineSteps)));
}
PT_HDI float DequantiseCos(uint32_t q) { return float(q) * (2.0f / float(kCosineSteps)) - 1.0f; }

}  // namespace pt
