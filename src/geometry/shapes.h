// Ray-shape intersection for the three shapes (triangle, parallelogram, sphere), the surface
// description rebuilt from a hit, and shape bounds. Everything here runs on host and device.
// Ray directions are unit length and origins are already pushed off their surface by
// OffsetRayOrigin, so there are no epsilons: a hit needs 0 < t < tMax, and each test rejects
// t that its own rounding error cannot tell from 0 (pbrt-v4's conservative tests).
#pragma once

#include "src/core/ray.h"
#include "src/geometry/aabb.h"
#include "src/geometry/instance.h"
#include "src/geometry/interaction.h"
#include "src/geometry/triangle_mt.h"
#include "src/materials/alpha.h"
#include "src/scene/scene_view.h"

namespace pt {

namespace detail {

// Component i of v by value. vec3::operator[] returns a reference, which makes nvcc spill the
// vector to local memory when i is not a compile-time constant; selects stay in registers.
PT_HDI float Component(vec3 v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : v.z); }

// a*b - c*d rounded twice and never fused into an FMA: the watertight test needs the edge
// function of a shared edge to come out as exactly the negation for the neighbouring triangle,
// and a contracted FMA rounds the two orders differently.
PT_HDI float EdgeFunction(float a, float b, float c, float d) {
#if PT_IS_GPU_CODE
  return __fsub_rn(__fmul_rn(a, b), __fmul_rn(c, d));
#else
  return a * b - c * d;
#endif
}

// The same in double: products of floats are exact there, so the sign is exact.
PT_HDI float EdgeFunctionDouble(float a, float b, float c, float d) {
  return float(double(a) * double(b) - double(c) * double(d));
}

PT_HDI float MaxAbs(float a, float b, float c) {
  return MaxIgnoreNan(MaxIgnoreNan(fabsf(a), fabsf(b)), fabsf(c));
}

// Per axis |a_y b_z| + |a_z b_y| etc.: bounds |cross(a, b)| including its rounding.
PT_HDI vec3 AbsCross(vec3 a, vec3 b) {
  return vec3(fabsf(a.y * b.z) + fabsf(a.z * b.y), fabsf(a.z * b.x) + fabsf(a.x * b.z),
              fabsf(a.x * b.y) + fabsf(a.y * b.x));
}

}  // namespace detail

// Per-ray constants of the watertight triangle test (Woop, Benthin, Wald 2013): the dominant
// axis of d becomes z, and a shear maps d onto +z. Traversal computes it once per ray.
struct TriangleRayData {
  int kx, ky, kz;
  float sx, sy, sz;
  vec3 invDir;  // for RaiseToBoxEntry (the traversals' own 1 / d: no registers of its own)

  PT_HDI_HOT static TriangleRayData Make(vec3 d) {
    TriangleRayData r;
    r.invDir = vec3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
    r.kz = MaxDimension(Abs(d));
    r.kx = r.kz == 2 ? 0 : r.kz + 1;
    r.ky = r.kx == 2 ? 0 : r.kx + 1;
    float dz = detail::Component(d, r.kz);
    r.sx = -detail::Component(d, r.kx) / dz;
    r.sy = -detail::Component(d, r.ky) / dz;
    r.sz = 1.0f / dz;
    return r;
  }

  // Vertex relative to the ray origin, permuted and sheared in x and y (z is scaled later).
  PT_HDI_HOT vec3 Transform(vec3 p, vec3 o) const {
    vec3 q = p - o;
    float z = detail::Component(q, kz);
    return vec3(detail::Component(q, kx) + sx * z, detail::Component(q, ky) + sy * z, z);
  }
};

// Watertight ray-triangle test; both faces hit. bary = (b1, b2) with
// p = (1 - b1 - b2) p0 + b1 p1 + b2 p2. Follows pbrt-v4's Triangle::Intersect in float, with
// the double-precision edge functions on an exact 0 and the conservative t > 0 test.
PT_HDI_HOT bool IntersectTriangle(const Triangle& tri, const Ray& ray, const TriangleRayData& rd,
                                  float tMax, float* tHit, vec2* bary) {
  vec3 p0t = rd.Transform(tri.p0, ray.o);
  vec3 p1t = rd.Transform(tri.p1, ray.o);
  vec3 p2t = rd.Transform(tri.p2, ray.o);

  float e0 = detail::EdgeFunction(p1t.x, p2t.y, p1t.y, p2t.x);
  float e1 = detail::EdgeFunction(p2t.x, p0t.y, p2t.y, p0t.x);
  float e2 = detail::EdgeFunction(p0t.x, p1t.y, p0t.y, p1t.x);
  if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
    e0 = detail::EdgeFunctionDouble(p1t.x, p2t.y, p1t.y, p2t.x);
    e1 = detail::EdgeFunctionDouble(p2t.x, p0t.y, p2t.y, p0t.x);
    e2 = detail::EdgeFunctionDouble(p0t.x, p1t.y, p0t.y, p1t.x);
  }
  if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f)) {
    return false;
  }
  float det = e0 + e1 + e2;
  if (det == 0.0f) return false;

  // Scaled distance. Unlike pbrt, tMax is tested only on the divided t, so whether a triangle
  // is accepted depends on its t alone, never on the order in which hits were found.
  p0t.z *= rd.sz;
  p1t.z *= rd.sz;
  p2t.z *= rd.sz;
  float tScaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
  if (det < 0.0f ? tScaled >= 0.0f : tScaled <= 0.0f) return false;
  float invDet = 1.0f / det;
  float t = tScaled * invDet;
  if (!(t < tMax)) return false;

  // t must exceed its own error bound (pbrt-v4, section 6.8.4) to count as > 0.
  float maxZt = detail::MaxAbs(p0t.z, p1t.z, p2t.z);
  float maxXt = detail::MaxAbs(p0t.x, p1t.x, p2t.x);
  float maxYt = detail::MaxAbs(p0t.y, p1t.y, p2t.y);
  float deltaZ = Gamma(3) * maxZt;
  // The shear adds s_x * z = -d_x * (z scaled): bound that term by |d_x| maxZt, not maxZt
  // (pbrt-v4's looser bound rejects real hits of grazing rays on small, distant triangles).
  float deltaX = Gamma(5) * (maxXt + fabsf(rd.sx / rd.sz) * maxZt);
  float deltaY = Gamma(5) * (maxYt + fabsf(rd.sy / rd.sz) * maxZt);
  float deltaE = 2.0f * (Gamma(2) * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
  float maxE = detail::MaxAbs(e0, e1, e2);
  float deltaT = 3.0f * (Gamma(3) * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * fabsf(invDet);
  if (t <= deltaT) return false;

  *tHit = t;
  *bary = vec2(e1 * invDet, e2 * invDet);
  return true;
}

PT_HDI bool IntersectTriangle(const Triangle& tri, const Ray& ray, float tMax, float* tHit,
                              vec2* bary) {
  return IntersectTriangle(tri, ray, TriangleRayData::Make(ray.d), tMax, tHit, bary);
}

// The parallelogram origin + s*u + t*v, s,t in [0, 1]; both faces hit. The plane distance
// N = dot(n, origin - o) must exceed its rounding bound (which also covers the rounding of
// n = cross(u, v)), so a ray spawned off this quad never re-hits it and a wrong sign of N
// never yields a hit.
PT_HDI bool IntersectQuad(const Quad& q, const Ray& ray, float tMax, float* tHit, vec2* st) {
  vec3 n = glm::cross(q.u, q.v);
  float denom = glm::dot(n, ray.d);
  vec3 toPlane = q.origin - ray.o;
  float num = glm::dot(n, toPlane);
  float t = num / denom;
  if (!(t > 0.0f && t < tMax)) return false;  // also rejects denom == 0 (NaN or inf)
  float numError = Gamma(6) * glm::dot(detail::AbsCross(q.u, q.v), Abs(q.origin) + Abs(ray.o));
  if (fabsf(num) <= numError) return false;

  vec3 rel = ray.d * t - toPlane;  // hit point relative to the quad origin
  float invNn = 1.0f / glm::dot(n, n);
  float s = glm::dot(n, glm::cross(rel, q.v)) * invNn;
  float tt = glm::dot(n, glm::cross(q.u, rel)) * invNn;
  if (!(s >= 0.0f && s <= 1.0f && tt >= 0.0f && tt <= 1.0f)) return false;
  *tHit = t;
  *st = vec2(s, tt);
  return true;
}

// Sphere test as Ray Tracing Gems ch. 7: with f = o - c and unit d, the discriminant is
// r^2 - |f - (f.d) d|^2 (no cancellation for distant origins), and the near root is c/q (no
// cancellation between -b and the square root). A root whose numerator c = |f|^2 - r^2 is
// within its rounding error of 0 sits at the ray origin: it is dropped, which is how a ray
// spawned from the sphere avoids re-hitting it. Hits from inside return the far root.
PT_HDI bool IntersectSphere(const Sphere& sph, const Ray& ray, float tMax, float* tHit) {
  vec3 f = ray.o - sph.center;
  float b = glm::dot(f, ray.d);
  vec3 perp = f - b * ray.d;
  float r2 = sph.radius * sph.radius;
  float disc = r2 - glm::dot(perp, perp);
  if (disc < 0.0f) return false;
  float ff = glm::dot(f, f);
  float c = ff - r2;
  float q = -b - copysignf(sqrtf(disc), b);
  bool nearUsable = fabsf(c) > Gamma(6) * (ff + r2);
  float tA = nearUsable ? c / q : -1.0f;  // q == 0 only when c == 0 too
  float tB = q;
  float tNear = tA < tB ? tA : tB, tFar = tA < tB ? tB : tA;
  float t = tNear > 0.0f ? tNear : tFar;
  if (!(t > 0.0f && t < tMax)) return false;
  *tHit = t;
  return true;
}

// ---- Bounds (conservative: rounding of computed corners is padded outwards) ----

PT_HDI Aabb TriangleBounds(const Triangle& tri) {
  Aabb b = Aabb::FromPoints(tri.p0, tri.p1);
  b.Extend(tri.p2);
  return b;
}

PT_HDI Aabb QuadBounds(const Quad& q) {
  Aabb b = Aabb::FromPoints(q.origin, q.origin + q.u);
  b.Extend(q.origin + q.v);
  b.Extend(q.origin + q.u + q.v);
  vec3 pad = Gamma(3) * (Abs(q.origin) + Abs(q.u) + Abs(q.v));
  b.lo -= pad;
  b.hi += pad;
  return b;
}

PT_HDI Aabb SphereBounds(const Sphere& sph) {
  vec3 r = vec3(fabsf(sph.radius));
  vec3 pad = Gamma(2) * (Abs(sph.center) + r);
  Aabb b;
  b.lo = sph.center - r - pad;
  b.hi = sph.center + r + pad;
  return b;
}

PT_HDI Aabb PrimBounds(const Triangle& tri) { return TriangleBounds(tri); }
PT_HDI Aabb PrimBounds(const Quad& q) { return QuadBounds(q); }
PT_HDI Aabb PrimBounds(const Sphere& sph) { return SphereBounds(sph); }

PT_HDI Aabb PrimBounds(const SceneView& s, uint32_t primIndex) {
  PrimRef ref = s.prims[primIndex];
  switch (ref.Type()) {
    case ShapeType::kTriangle:
      return PrimBounds(s.triangles[ref.Index()]);
    case ShapeType::kQuad:
      return PrimBounds(s.quads[ref.Index()]);
    default:
      return PrimBounds(s.spheres[ref.Index()]);
  }
}

// ---- Dispatch over PrimRef ----

// The geometric test alone.
PT_HDI bool IntersectShape(const SceneView& s, PrimRef ref, const Ray& ray,
                           const TriangleRayData& rd, float tMax, float* tHit, vec2* uv) {
  switch (ref.Type()) {
    case ShapeType::kTriangle:
      if (s.triangleTest == kTriTestMollerTrumbore)  // --tri-test mt, for the robustness study
        return IntersectTriangleMollerTrumbore(s.triangles[ref.Index()], ray, tMax, tHit, uv);
      return IntersectTriangle(s.triangles[ref.Index()], ray, rd, tMax, tHit, uv);
    case ShapeType::kQuad:
      return IntersectQuad(s.quads[ref.Index()], ray, tMax, tHit, uv);
    case ShapeType::kSphere:
      *uv = vec2(0.0f);
      return IntersectSphere(s.spheres[ref.Index()], ray, tMax, tHit);
    default:
      return false;
  }
}

namespace detail {

#if PT_IS_GPU_CODE
// A float loaded again by a volatile load, which the compiler cannot merge with an earlier
// load of it: so the registers of the shape test's own loads are not held until the raise.
PT_HDI float Reload(const float* p) {
  float v;
  asm volatile("ld.global.nc.f32 %0, [%1];" : "=f"(v) : "l"(p));
  return v;
}
#else
PT_HDI float Reload(const float* p) { return *p; }
#endif

// The corner of primitive i's box (as the BVH has it: PrimBounds) on the ray's near side,
// from the scene arrays read again.
PT_HDI vec3 NearCornerOfPrim(const SceneView& s, uint32_t i, vec3 invDir) {
  // The packed copy (in BVH order) when it holds a triangle, as IntersectPrimUnraised reads it.
  Aabb box;
  if (s.packedTriangles != nullptr &&
      ShapeType(s.packedTriangles[i].tag >> 30) == ShapeType::kTriangle) {
    const float* p = &s.packedTriangles[i].p0.x;
    Triangle tri;
    for (int a = 0; a < 3; ++a) {
      tri.p0[a] = Reload(p + a);
      tri.p1[a] = Reload(p + 4 + a);
      tri.p2[a] = Reload(p + 8 + a);
    }
    box = TriangleBounds(tri);
  } else {
    box = PrimBounds(s, i);
  }
  return vec3(invDir.x < 0.0f ? box.hi.x : box.lo.x, invDir.y < 0.0f ? box.hi.y : box.lo.y,
              invDir.z < 0.0f ? box.hi.z : box.lo.z);
}

// A hit's distance raised to its primitive's box's computed entry (ShapeBoxEntry); false when
// that leaves it at or past tMax. Done here, once a shape test has hit, with the primitive read
// again, rather than inside the tests: keeping their inputs live for it cost the GPU's
// traversal kernels 6-14 registers (benchmarks/RESULTS.md, fourth session of 2026-11-25).
PT_HDI bool RaiseToBoxEntry(const SceneView& s, uint32_t i, const Ray& ray,
                            const TriangleRayData& rd, float tMax, float* tHit) {
  const float entry = ShapeBoxEntry(NearCornerOfPrim(s, i, rd.invDir), ray.o, rd.invDir);
  if (!(entry > *tHit)) return true;
  *tHit = entry;
  return entry < tMax;
}

}  // namespace detail

// Every traversal's primitive test: the shape, then, for primitives flagged kHitTestBit only,
// the material's verdict on the hit (alpha, back-face culling; src/materials/alpha.h). On a
// rejected hit *tHit and *uv may hold the rejected values; the caller must not use them.
// kHitTest false compiles the verdict out (a scene none of whose materials asks for one): the
// test's texture code would otherwise cost every traversal kernel registers.
template <bool kHitTest = true>
PT_HDI bool IntersectPrimUnraised(const SceneView& s, uint32_t primIndex, const Ray& ray,
                                  const TriangleRayData& rd, float tMax, float* tHit, vec2* uv) {
  // Triangles come from the packed copy in BVH order (three 16-byte loads, no PrimRef first);
  // its tag is the PrimRef's, so the hit-test bit is known without another load.
  if (s.packedTriangles != nullptr && s.triangleTest != kTriTestMollerTrumbore) {
#if PT_IS_GPU_CODE
    const float4* q = reinterpret_cast<const float4*>(s.packedTriangles + primIndex);
    const float4 a = __ldg(q);
    const uint32_t tag = __float_as_uint(a.w);
    if (ShapeType(tag >> 30) == ShapeType::kTriangle) {
      const float4 b = __ldg(q + 1), c = __ldg(q + 2);
      if (!IntersectTriangle(Triangle{vec3(a.x, a.y, a.z), vec3(b.x, b.y, b.z), vec3(c.x, c.y, c.z)},
                             ray, rd, tMax, tHit, uv))
        return false;
      if constexpr (!kHitTest) return true;
      else return (tag & PrimRef::kHitTestBit) == 0 || AcceptHit(s, s.prims[primIndex], ray, *uv);
    }
#else
    const PackedTriangle& p = s.packedTriangles[primIndex];
    if (ShapeType(p.tag >> 30) == ShapeType::kTriangle) {
      if (!IntersectTriangle(Triangle{p.p0, p.p1, p.p2}, ray, rd, tMax, tHit, uv)) return false;
      if constexpr (!kHitTest) return true;
      else return (p.tag & PrimRef::kHitTestBit) == 0 || AcceptHit(s, s.prims[primIndex], ray, *uv);
    }
#endif
  }
  PrimRef ref = s.prims[primIndex];
  if (!IntersectShape(s, ref, ray, rd, tMax, tHit, uv)) return false;
  if constexpr (!kHitTest) return true;
  else return !ref.NeedsHitTest() || AcceptHit(s, ref, ray, *uv);
}

// The primitive test every traversal and brute force use. With --tri-test box-clamped a hit is
// never before its primitive's box (ShapeBoxEntry), so no tree's culling can change which of
// coincident surfaces is closest. That costs the GPU 7-29% of render time, so it is a choice,
// compiled into the kHitTest variants only (the renderer runs those for it): the others keep
// their registers.
template <bool kHitTest = true>
PT_HDI bool IntersectPrim(const SceneView& s, uint32_t primIndex, const Ray& ray,
                          const TriangleRayData& rd, float tMax, float* tHit, vec2* uv) {
  if (!IntersectPrimUnraised<kHitTest>(s, primIndex, ray, rd, tMax, tHit, uv)) return false;
  if constexpr (kHitTest) {
    if (s.triangleTest == kTriTestBoxClamped)
      return detail::RaiseToBoxEntry(s, primIndex, ray, rd, tMax, tHit);
  }
  return true;
}

PT_HDI bool IntersectPrim(const SceneView& s, uint32_t primIndex, const Ray& ray, float tMax,
                          float* tHit, vec2* uv) {
  return IntersectPrim(s, primIndex, ray, TriangleRayData::Make(ray.d), tMax, tHit, uv);
}

// ---- Surface interaction ----

namespace detail {

PT_HDI void TriangleSurface(const SceneView& s, uint32_t index, vec2 bary, SurfaceInteraction* si) {
  const Triangle& tri = s.triangles[index];
  float b1 = bary.x, b2 = bary.y, b0 = 1.0f - b1 - b2;
  // p0 + b1 e1 + b2 e2 rather than pbrt's sum b_i p_i: b0 = 1 - b1 - b2 is rounded in
  // absolute terms, so b0 p0 can be off by eps |p0| where the bound only allows gamma(7) b0 |p0|.
  // Here the exact value is on the triangle's plane whatever b1 and b2 are.
  vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  vec3 t1 = b1 * e1, t2 = b2 * e2;
  si->p = tri.p0 + t1 + t2;
  si->pError = Gamma(7) * (Abs(tri.p0) + Abs(t1) + Abs(t2));
  si->ng = glm::normalize(glm::cross(e1, e2));
  si->ns = si->ng;
  if (s.triangleNormals == nullptr) return;
  const TriangleNormals& tn = s.triangleNormals[index];
  vec3 ns = b0 * tn.n0 + b1 * tn.n1 + b2 * tn.n2;
  float len2 = glm::dot(ns, ns);
  if (!(len2 > 0.0f && len2 < kInfinity)) return;  // no vertex normals (all zero), or cancelled
  ns *= 1.0f / sqrtf(len2);
  si->ns = glm::dot(ns, si->ng) < 0.0f ? -ns : ns;
}

PT_HDI void QuadSurface(const Quad& q, vec2 st, SurfaceInteraction* si) {
  vec3 su = st.x * q.u, tv = st.y * q.v;
  si->p = q.origin + su + tv;
  si->pError = Gamma(7) * (Abs(q.origin) + Abs(su) + Abs(tv));
  si->ng = glm::normalize(glm::cross(q.u, q.v));
  si->ns = si->ng;
}

// Reprojects o + t d onto the sphere. The local offset has error gamma(5)|local| (pbrt-v4's
// object-space bound); adding the world-space centre rounds once more (gamma(2)|p| is generous).
PT_HDI void SphereSurface(const Sphere& sph, const Ray& ray, float t, SurfaceInteraction* si) {
  vec3 local = (ray.o + t * ray.d) - sph.center;
  float len = glm::length(local);
  vec3 n = len > 0.0f ? local / len : vec3(0.0f, 1.0f, 0.0f);
  local = sph.radius * n;
  si->p = sph.center + local;
  si->pError = Gamma(5) * Abs(local) + Gamma(2) * Abs(si->p);
  si->ng = n;
  si->ns = n;
  // (phi, theta) about +Y (the scene's up), each mapped to [0, 1].
  float phi = atan2f(n.z, n.x);
  if (phi < 0.0f) phi += 2.0f * kPi;
  si->uv = vec2(phi * (0.5f * kInvPi), acosf(fminf(fmaxf(n.y, -1.0f), 1.0f)) * kInvPi);
}

}  // namespace detail

// The surface at a hit (hit.prim != kNoHit) in the space of its primitive: world space in a flat
// scene, the mesh's object space for an instance (MakeInteraction places it).
// uv: triangle (b1, b2), quad (s, t), sphere (phi / 2pi, theta / pi) about +Y.
PT_HDI SurfaceInteraction MakeObjectInteraction(const SceneView& s, const Ray& ray,
                                                const HitRecord& hit) {
  PrimRef ref = s.prims[hit.prim];
  SurfaceInteraction si;
  si.uv = hit.uv;
  si.material = ref.material;
  si.light = ref.light;
  switch (ref.Type()) {
    case ShapeType::kTriangle:
      detail::TriangleSurface(s, ref.Index(), hit.uv, &si);
      break;
    case ShapeType::kQuad:
      detail::QuadSurface(s.quads[ref.Index()], hit.uv, &si);
      break;
    default:
      detail::SphereSurface(s.spheres[ref.Index()], ray, hit.t, &si);
      break;
  }
  return si;  // texture coordinates: src/materials/surface_attributes.h
}

// The surface at any hit: on an instance, found in object space and then placed in the world
// with the instance's material and the light of that placement's triangle.
PT_HDI SurfaceInteraction MakeInteraction(const SceneView& s, const Ray& ray,
                                          const HitRecord& hit) {
  SurfaceInteraction si = MakeObjectInteraction(s, ray, hit);
  if (hit.instance == kNoInstance) return si;
  const Instance& inst = s.instances[hit.instance];
  si.light = InstanceLight(inst, si.light, s.prims[hit.prim].Index());
  InstanceToWorld(inst, &si);
  return si;
}

}  // namespace pt
