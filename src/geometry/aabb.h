// Axis-aligned bounding boxes and the conservative ray-box slab test used by BVH traversal.
#pragma once

#include "src/core/math.h"

namespace pt {

// Starts empty (lo = +inf, hi = -inf) so that Extend and Union need no special first case.
struct Aabb {
  vec3 lo = vec3(kInfinity);
  vec3 hi = vec3(-kInfinity);

  PT_HDI static Aabb Empty() { return Aabb(); }
  PT_HDI static Aabb FromPoints(vec3 a, vec3 b) {
    Aabb box;
    box.lo = vec3(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z));
    box.hi = vec3(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z));
    return box;
  }

  // False for the empty box and for any box with a NaN coordinate.
  PT_HDI bool IsEmpty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }

  // fminf/fmaxf ignore a NaN operand, so one bad point cannot poison a whole box.
  PT_HDI void Extend(vec3 p) {
    lo = vec3(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
    hi = vec3(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
  }
  PT_HDI void Extend(const Aabb& b) {
    lo = vec3(fminf(lo.x, b.lo.x), fminf(lo.y, b.lo.y), fminf(lo.z, b.lo.z));
    hi = vec3(fmaxf(hi.x, b.hi.x), fmaxf(hi.y, b.hi.y), fmaxf(hi.z, b.hi.z));
  }

  PT_HDI vec3 Centroid() const { return 0.5f * lo + 0.5f * hi; }
  PT_HDI vec3 Diagonal() const { return IsEmpty() ? vec3(0.0f) : hi - lo; }
  PT_HDI float SurfaceArea() const {
    vec3 d = Diagonal();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  PT_HDI bool Contains(vec3 p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
           p.z <= hi.z;
  }
  PT_HDI bool Contains(const Aabb& b) const { return Contains(b.lo) && Contains(b.hi); }
};

PT_HDI Aabb Union(const Aabb& a, const Aabb& b) {
  Aabb r = a;
  r.Extend(b);
  return r;
}

PT_HDI Aabb Union(const Aabb& a, vec3 p) {
  Aabb r = a;
  r.Extend(p);
  return r;
}

// Slab test against [lo, hi] for t in [0, tMax]; writes the entry distance (>= 0) on a hit.
// Conservative (Ize 2013, "Robust BVH Ray Traversal"): each slab's far distance is scaled by
// 1 + 2*gamma(3), which covers the rounding of (bound - o) * invDir and of invDir = 1 / d, so a
// ray that exactly touches a box is never culled and no ray slips between two triangles that
// share an edge but live in different leaves. The near plane is picked by the sign of invDir
// (not by comparing the two distances), so an empty box (lo = +inf, hi = -inf) always misses.
// A NaN from 0 * inf (the ray runs inside a slab plane) is ignored by the comparisons below,
// which keeps such rays inside that slab.
PT_HDI bool IntersectAabb(vec3 lo, vec3 hi, vec3 o, vec3 invDir, float tMax, float* tEntry) {
  constexpr float kFarScale = 1.0f + 2.0f * Gamma(3);
  float t0 = 0.0f;
  float t1 = tMax;
  for (int axis = 0; axis < 3; ++axis) {
    float inv = axis == 0 ? invDir.x : (axis == 1 ? invDir.y : invDir.z);
    float org = axis == 0 ? o.x : (axis == 1 ? o.y : o.z);
    float l = axis == 0 ? lo.x : (axis == 1 ? lo.y : lo.z);
    float h = axis == 0 ? hi.x : (axis == 1 ? hi.y : hi.z);
    bool negative = signbit(inv);
    float tNear = ((negative ? h : l) - org) * inv;
    float tFar = ((negative ? l : h) - org) * inv * kFarScale;
    t0 = tNear > t0 ? tNear : t0;
    t1 = tFar < t1 ? tFar : t1;
  }
  if (t0 > t1) return false;
  *tEntry = t0;
  return true;
}

}  // namespace pt
