// Axis-aligned bounding boxes and the conservative ray-box slab test used by BVH traversal.
#pragma once

#include "src/core/math.h"

namespace pt {

namespace detail {

// min/max that ignore a NaN in b (a must not be NaN). The GPU has one instruction for fminf;
// on the host fminf is a libm call unless -ffast-math, so the host uses a compare and select.
PT_HDI float MinIgnoreNan(float a, float b) {
#if PT_IS_GPU_CODE
  return fminf(a, b);
#else
  return b < a ? b : a;
#endif
}
PT_HDI float MaxIgnoreNan(float a, float b) {
#if PT_IS_GPU_CODE
  return fmaxf(a, b);
#else
  return b > a ? b : a;
#endif
}
PT_HDI vec3 MinIgnoreNan(vec3 a, vec3 b) {
  return vec3(MinIgnoreNan(a.x, b.x), MinIgnoreNan(a.y, b.y), MinIgnoreNan(a.z, b.z));
}
PT_HDI vec3 MaxIgnoreNan(vec3 a, vec3 b) {
  return vec3(MaxIgnoreNan(a.x, b.x), MaxIgnoreNan(a.y, b.y), MaxIgnoreNan(a.z, b.z));
}

}  // namespace detail

// Starts empty (lo = +inf, hi = -inf) so that Extend and Union need no special first case.
struct Aabb {
  vec3 lo = vec3(kInfinity);
  vec3 hi = vec3(-kInfinity);

  PT_HDI static Aabb Empty() { return Aabb(); }
  PT_HDI static Aabb FromPoints(vec3 a, vec3 b) {
    Aabb box;
    box.Extend(a);
    box.Extend(b);
    return box;
  }

  // True for the empty box, and for any box with a NaN coordinate.
  PT_HDI bool IsEmpty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }

  // A NaN coordinate of the argument is ignored, so one bad point cannot poison a whole box.
  PT_HDI void Extend(vec3 p) {
    lo = detail::MinIgnoreNan(lo, p);
    hi = detail::MaxIgnoreNan(hi, p);
  }
  PT_HDI void Extend(const Aabb& b) {
    lo = detail::MinIgnoreNan(lo, b.lo);
    hi = detail::MaxIgnoreNan(hi, b.hi);
  }

  PT_HDI vec3 Centroid() const { return 0.5f * lo + 0.5f * hi; }
  PT_HDI vec3 Diagonal() const { return IsEmpty() ? vec3(0.0f) : hi - lo; }
  PT_HDI float SurfaceArea() const {
    vec3 d = Diagonal();
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  PT_HDI bool Contains(vec3 p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
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

// Rounding can put a shape's computed hit distance a little before the exact distance at
// which the ray enters the shape's own box (6e-6 relative on coplanar triangles of the
// Breakfast Room). A node box holding that box may then already be culled by another hit at
// about the same distance, and which of two coincident surfaces wins would depend on the
// tree. So --tri-test box-clamped (shapes.h) raises a hit's distance to at least this
// computed entry distance of the shape's box, from its corner on the ray's near side: each
// slab distance (b - o) * (1 / d) is within gamma(3) (relative) of exact, as the node tests'
// entry distances are, and the far scales below cover both (see kAabbFarScale). A NaN slab
// distance (0 * inf: the ray runs in a slab plane) is ignored, and +inf (it runs beside the
// box) gives 0: no raise. Exact cases stay exact (a ray along -z from the origin meets z = -2
// at t = 2).
PT_HDI float ShapeBoxEntry(vec3 nearCorner, vec3 o, vec3 invDir) {
  const vec3 s = (nearCorner - o) * invDir;
  const float t =
      detail::MaxIgnoreNan(detail::MaxIgnoreNan(detail::MaxIgnoreNan(0.0f, s.x), s.y), s.z);
  return t < kInfinity ? t : 0.0f;
}

// Scale of a box test's far distance (and tMax with it). Ize 2013 ("Robust BVH Ray
// Traversal"): 1 + 2 gamma(3) covers the rounding of (bound - o) * invDir and of invDir = 1 / d
// on both the near and far sides. Culling by a hit also has to allow for that hit's distance
// being raised only to its shape's computed box entry (ShapeBoxEntry), up to gamma(3) below
// the exact one, while the node's computed entry may be gamma(3) above the exact one:
// 1 + 2 gamma(5) covers both ratios and the rounding of the product.
constexpr float kAabbFarScale = 1.0f + 2.0f * Gamma(5);

// Slab test against [lo, hi] for t in [0, tMax]; writes the entry distance (>= 0) on a hit.
// Conservative: the far distances, and tMax with them, are scaled by kAabbFarScale, so a ray that
// exactly touches a box is never culled, no ray slips between two triangles that share an edge
// but live in different leaves, and a box is not culled by a hit at (almost) its entry distance.
// The near plane is picked by the sign of invDir (not by comparing the two distances), so an
// empty box (lo = +inf, hi = -inf) always misses. A NaN from 0 * inf (the ray runs inside a slab
// plane) is ignored by the comparisons below, which keeps such rays inside that slab.
PT_HDI bool IntersectAabb(vec3 lo, vec3 hi, vec3 o, vec3 invDir, float tMax, float* tEntry) {
  float t0 = 0.0f;
  float t1 = tMax;
  for (int axis = 0; axis < 3; ++axis) {
    float inv = axis == 0 ? invDir.x : (axis == 1 ? invDir.y : invDir.z);
    float org = axis == 0 ? o.x : (axis == 1 ? o.y : o.z);
    float l = axis == 0 ? lo.x : (axis == 1 ? lo.y : lo.z);
    float h = axis == 0 ? hi.x : (axis == 1 ? hi.y : hi.z);
    bool negative = inv < 0.0f;  // 1/d is never -0, and 1/-0 = -inf counts as negative
    float tNear = ((negative ? h : l) - org) * inv;
    float tFar = ((negative ? l : h) - org) * inv;
    t0 = detail::MaxIgnoreNan(t0, tNear);
    t1 = detail::MinIgnoreNan(t1, tFar);
  }
  // min(tMax, tFar_i) * scale == min(tMax * scale, tFar_i * scale): rounding is monotonic.
  if (t0 > t1 * kAabbFarScale) return false;
  *tEntry = t0;
  return true;
}

}  // namespace pt
