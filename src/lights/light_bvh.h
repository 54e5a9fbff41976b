// Choosing a finite light through the light BVH (Conty Estevez and Kulla 2018, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting"; the form of pbrt-v4's BVHLightSampler):
// from the root, each step picks one of two children with probability proportional to its
// importance at the shading point, an estimate of what the lights below deliver there from
// their power, distance, emission cone and the receiver's normal. The probability of a given
// light is the product of those choices along its path, which LightTreePmf walks again from
// the root by the light's bit trail, with the very same importance arithmetic, so the pmf of a
// BSDF-sampled hit is bit for bit the probability next-event estimation would have chosen it.
//
// Importance is only a heuristic: where it is 0 (a light wholly behind the receiver, or
// outside its emission cone) next-event estimation never picks the light, LightTreePmf says 0,
// and a BSDF-sampled hit keeps its full weight, so the estimate stays unbiased.
#pragma once

#include "src/lights/light_bvh_types.h"
#include "src/scene/scene_view.h"

namespace pt {

// Where light arrives: the point, and the receiver's unit normal on the side it gathers from
// (zero: no normal, orientation at the point is ignored), two-sided where it also transmits.
struct LightRef {
  vec3 p = vec3(0.0f);
  vec3 n = vec3(0.0f);
  bool twoSided = true;
};

// The receiver's normal as path state keeps it between a vertex and the next (4 bytes):
// octahedral, with the two-sided flag in the lowest bit; kNoReceiver means no normal.
constexpr uint32_t kNoReceiver = 0xffffffffu;

PT_HDI uint32_t PackReceiver(vec3 n, bool twoSided) {
  uint32_t code = (EncodeOctahedral(n) & ~1u) | (twoSided ? 1u : 0u);
  return code == kNoReceiver ? kNoReceiver - 2u : code;  // keeps the flag, moves the axis a hair
}

// The reference next-event estimation and the pmf at the next vertex both use: the normal
// decoded from its packed form, so the two see the same bits.
PT_HDI LightRef ReceiverRef(vec3 p, uint32_t code) {
  LightRef r;
  r.p = p;
  if (code == kNoReceiver) return r;
  r.n = DecodeOctahedral(code & ~1u);
  r.twoSided = (code & 1u) != 0;
  return r;
}

// Bounds of what a set of lights emits: their box, total intensity scale phi, and the cone of
// emission, the normals within theta_o of w and light leaving each normal within theta_e.
struct LightBounds {
  vec3 lo = vec3(kInfinity), hi = vec3(-kInfinity);
  vec3 w = vec3(0.0f, 0.0f, 1.0f);
  float phi = 0.0f;
  float cosTheta_o = 1.0f, cosTheta_e = 1.0f;
  bool twoSided = false;
  bool flat = false;  // one-sided flat emitters whose normals are all w
};

// cos(max(0, a - b)) and sin(max(0, a - b)) of angles a, b in [0, pi] given their sin and cos.
PT_HDI float CosSubClamped(float sinA, float cosA, float sinB, float cosB) {
  return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}
PT_HDI float SinSubClamped(float sinA, float cosA, float sinB, float cosB) {
  return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}

// A bound on cos(a, p - x) over every point x of a box (centre c, half extents `half`, d = p -
// c) at distance dc > 0 from p: dot(a, p - x) <= dot(a, d) + dot(|a|, half) and |p - x| >= dc.
// (Two-sided: on |cos|.) Where a large box is near the point this is far tighter than the cone
// of the box's bounding sphere, which from inside that sphere bounds nothing: from a street
// below a plane of downward lamps, the neighbouring blocks' lamps are seen at grazing angles.
PT_HDI float BoxCosBound(vec3 a, vec3 d, vec3 half, float dc, bool twoSided) {
  float h = glm::dot(a, d), spread = glm::dot(Abs(a), half);
  float hi = (twoSided ? fabsf(h) : h) + spread;
  float c = hi / dc;
  return hi > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;  // (not fminf: GCC calls libm on the host)
}

// The smaller of two bounds on a cosine, kept at least kBoxCosFloor (or the first bound, if
// lower): the box bound only sharpens the importance, and the floor keeps a light the first
// bound lets through from a zero choice probability when float rounding makes the box bound 0.
constexpr float kBoxCosFloor = 1e-3f;
PT_HDI float TightenCos(float sphereBound, float boxBound) {
  float floor = sphereBound < kBoxCosFloor ? sphereBound : kBoxCosFloor;
  float c = sphereBound < boxBound ? sphereBound : boxBound;
  return c > floor ? c : floor;
}

// A bound on the emission cosine of lights b towards the point (1: omnidirectional), from
// wi, the unit direction from the box centre to the point, widened by the cone (sinB, cosB)
// the box fills from the point. At most b.cosTheta_e where no light emits towards the point.
PT_HDI float EmissionCosBound(const LightBounds& b, vec3 wi, float sinB, float cosB) {
  if (!(b.cosTheta_o > -1.0f)) return 1.0f;
  float cosW = glm::dot(b.w, wi);
  if (b.twoSided) cosW = fabsf(cosW);
  float sin2W = 1.0f - cosW * cosW, sin2O = 1.0f - b.cosTheta_o * b.cosTheta_o;
  float sinW = sqrtf(sin2W > 0.0f ? sin2W : 0.0f), sinO = sqrtf(sin2O > 0.0f ? sin2O : 0.0f);
  // The smallest angle between an emitting normal and a direction to the point.
  float cosX = CosSubClamped(sinW, cosW, sinO, b.cosTheta_o);
  float sinX = SinSubClamped(sinW, cosW, sinO, b.cosTheta_o);
  return CosSubClamped(sinX, cosX, sinB, cosB);
}

// cosP (EmissionCosBound's, above b.cosTheta_e) sharpened by BoxCosBound for a point outside
// the box (dc > 0, d = p - centre): the normals lie within theta_o of the axis w.
PT_HDI float SharpenEmissionCos(const LightBounds& b, float cosP, vec3 d, vec3 half, float dc) {
  if (!(dc > 0.0f) || !(b.cosTheta_o > -1.0f)) return cosP;
  float cosW = BoxCosBound(b.w, d, half, dc, b.twoSided);
  float sin2O = 1.0f - b.cosTheta_o * b.cosTheta_o;
  float sinO = sqrtf(sin2O > 0.0f ? sin2O : 0.0f);
  return TightenCos(cosP, CosSubClamped(sqrtf(1.0f - cosW * cosW), cosW, sinO, b.cosTheta_o));
}

// Importance of lights with bounds b at r: phi times a bound on the emission cosine towards
// the point, over the squared distance to the box centre (at least the box's half-diagonal
// squared, so a point inside or near the box does not blow up), times a bound on the
// receiver's cosine when it has a normal. The angle the box subtends from the point widens
// both cosine bounds, so a box near the point's horizon still counts; from outside the box,
// BoxCosBound sharpens both.
PT_HDI float LightImportance(const LightBounds& b, const LightRef& r) {
  vec3 centre = 0.5f * (b.lo + b.hi), half = 0.5f * (b.hi - b.lo);
  vec3 d = r.p - centre;
  bool hasNormal = r.n.x != 0.0f || r.n.y != 0.0f || r.n.z != 0.0f;
  float dist2 = glm::dot(d, d);
  float radius2 = glm::dot(half, half);
  // Exact for boxes, where the cone bounds below are loose near the point: flat emitters all
  // facing away from it (each emits only where dot(w, p - x) > 0), or a box wholly below a
  // one-sided receiver's horizon (light arrives only where dot(n, x - p) > 0). The node's axis
  // is the emitters' normal rounded (octahedral, ~3e-5 rad), so the flat test keeps a slack of
  // 1e-3 x a bound on |p - x|: a light seen at a grazing angle is never given importance 0.
  constexpr float kFlatSlack = 1e-3f;
  if (b.flat && glm::dot(b.w, d) + glm::dot(Abs(b.w), half) +
                        kFlatSlack * sqrtf(2.0f * (dist2 + radius2)) <= 0.0f)
    return 0.0f;
  if (!r.twoSided && hasNormal && glm::dot(r.n, d) >= glm::dot(Abs(r.n), half)) return 0.0f;
  float d2 = dist2 > radius2 ? dist2 : radius2;
  if (!(d2 > 0.0f)) return 0.0f;  // a point light at the point: no direction to it
  vec3 wi = dist2 > 0.0f ? d * (1.0f / sqrtf(dist2)) : vec3(0.0f);  // lights to the point
  vec3 outside = glm::max(Abs(d) - half, vec3(0.0f));
  float dc2 = glm::dot(outside, outside);  // squared distance from the point to the box
  float dc = dc2 > 0.0f ? sqrtf(dc2) : 0.0f;
  // The cone of directions the box fills as seen from the point (all of them from inside).
  // (Ternaries, not fmaxf: GCC calls libm for fmaxf on the host.)
  float sinB = 0.0f, cosB = -1.0f;
  if (dist2 > radius2) {
    float sin2B = radius2 / dist2;
    sinB = sqrtf(sin2B);
    cosB = sqrtf(1.0f - sin2B);
  }
  float cosP = EmissionCosBound(b, wi, sinB, cosB);
  if (cosP <= b.cosTheta_e) return 0.0f;
  float importance = b.phi * SharpenEmissionCos(b, cosP, d, half, dc) / d2;
  if (hasNormal) {
    float cosI = -glm::dot(wi, r.n);
    if (r.twoSided) cosI = fabsf(cosI);
    float sin2I = 1.0f - cosI * cosI;
    float cosR = CosSubClamped(sqrtf(sin2I > 0.0f ? sin2I : 0.0f), cosI, sinB, cosB);
    if (dc > 0.0f && cosR > 0.0f)
      cosR = TightenCos(cosR, BoxCosBound(-r.n, d, half, dc, r.twoSided));
    importance *= cosR > 0.0f ? cosR : 0.0f;
  }
  return importance;
}

// A node's bounds as LightImportance takes them.
PT_HDI LightBounds DecodeLightNode(const LightTreeView& t, const LightBvhNode& n) {
  LightBounds b;
  b.lo = t.lo + vec3(float(n.qlo[0]), float(n.qlo[1]), float(n.qlo[2])) * t.scale;
  b.hi = t.lo + vec3(float(n.qhi[0]), float(n.qhi[1]), float(n.qhi[2])) * t.scale;
  b.w = DecodeOctahedral(n.axis);
  b.phi = n.phi;
  b.cosTheta_o = DequantiseCos(n.cosines & kCosineSteps);
  b.cosTheta_e = DequantiseCos((n.cosines >> 15) & kCosineSteps);
  b.twoSided = ((n.cosines >> 30) & 1u) != 0;
  b.flat = (n.cosines >> 31) != 0;
  return b;
}

PT_HDI float NodeImportance(const SceneView& s, uint32_t node, const LightRef& r) {
  return LightImportance(DecodeLightNode(s.lightTree, s.lightNodes[node]), r);
}

// Below this probability the choice draws on uRefresh: a float's 24 bits would otherwise run
// out deep in a large tree, and the frequencies drift from the pmf.
constexpr float kLightTreeRefresh = 1.0f / 4096.0f;

// Chooses a light of the tree at r with u (and uRefresh once the path's probability falls below
// kLightTreeRefresh; negative: never). False when the tree is empty or every light's
// importance is 0 there; otherwise *light and its probability *pmf (LightTreePmf's value).
PT_HDI bool SampleLightTree(const SceneView& s, const LightRef& r, float u, float uRefresh,
                            int* light, float* pmf) {
  if (s.lightTree.nodeCount == 0) return false;
  uint32_t k = 0;
  float p = 1.0f;
  while (!s.lightNodes[k].IsLeaf()) {
    if (uRefresh >= 0.0f && p < kLightTreeRefresh) {
      u = uRefresh;
      uRefresh = -1.0f;
    }
    uint32_t c = s.lightNodes[k].child;
    float c0 = NodeImportance(s, c, r), c1 = NodeImportance(s, c + 1, r);
    float sum = c0 + c1;
    if (!(sum > 0.0f) || !(sum < kInfinity)) return false;
    float p0 = c0 / sum;
    if (u < p0) {
      k = c;
      u = u / p0;
      p *= p0;
    } else {
      float p1 = c1 / sum;
      k = c + 1;
      u = fminf((u - p0) / p1, 0x1.fffffep-1f);
      p *= p1;
    }
  }
  // A single light is chosen with probability 1 wherever it is (its importance would only
  // say where it cannot reach, which its sample says too): the power table's cost.
  *light = int(s.lightNodes[k].Light());
  *pmf = p;
  return p > 0.0f;
}

// The probability SampleLightTree at r chooses `light` (0 for lights outside the tree).
PT_HDI float LightTreePmf(const SceneView& s, const LightRef& r, uint32_t light) {
  if (s.lightTree.nodeCount == 0 || light >= s.lightTree.boundedCount) return 0.0f;
  uint64_t trail = s.lightTrails[light];
  if (trail == 0) return 0.0f;
  if (trail == 1) return 1.0f;  // a single light (SampleLightTree)
  uint32_t k = 0;
  float p = 1.0f;
  for (; trail != 1; trail >>= 1) {
    uint32_t c = s.lightNodes[k].child;
    float c0 = NodeImportance(s, c, r), c1 = NodeImportance(s, c + 1, r);
    float sum = c0 + c1;
    if (!(sum > 0.0f) || !(sum < kInfinity)) return 0.0f;
    bool second = (trail & 1u) != 0;
    p *= (second ? c1 : c0) / sum;
    k = c + (second ? 1u : 0u);
  }
  return p;
}

}  // namespace pt
