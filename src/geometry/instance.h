// Moving rays into an instance's object space and hits back into world space, with the
// floating-point error bounds pbrt-v4 keeps for transformed shapes, so that ray offsets stay
// conservative (no self-intersection) whatever the instance's scale, rotation or mirroring.
#pragma once

#include "src/core/ray.h"
#include "src/geometry/interaction.h"
#include "src/scene/instance_types.h"
#include "src/scene/scene_types.h"

namespace pt {

// The world ray in the instance's object space (pbrt-v4 Transform::operator()(Ray, tMax)). The
// direction is not normalised, so the parameter t means the same point in both spaces. The
// origin's rounding error (gamma(3) per row) could put it behind the surface it leaves; it is
// moved forward along the ray past that error, by *dt, so a hit at object-space t is at world
// t + *dt (and a world limit tMax is tMax - *dt in object space).
PT_HDI Ray ObjectRay(const Instance& inst, const Ray& ray, float* dt) {
  Ray r;
  r.o = inst.toObject.Point(ray.o);
  r.d = inst.toObject.Vector(ray.d);
  vec3 oError = Gamma(3) * inst.toObject.AbsPointSum(ray.o);
  float lengthSquared = glm::dot(r.d, r.d);
  *dt = 0.0f;
  if (lengthSquared > 0.0f) {
    *dt = glm::dot(Abs(r.d), oError) / lengthSquared;
    r.o += r.d * *dt;
  }
  return r;
}

// A point with its absolute error bound, to world space (pbrt-v4 Transform of a Point3fi): the
// rounding of the transform itself plus the propagated object-space error.
PT_HDI void PointToWorld(const Affine3& m, vec3* p, vec3* pError) {
  vec3 e = Gamma(3) * m.AbsPointSum(*p) + (1.0f + Gamma(3)) * m.AbsVector(*pError);
  *p = m.Point(*p);
  *pError = e;
}

// A normal to world space: the inverse transpose of toWorld, i.e. the transpose of toObject's
// linear part. It keeps pointing to the side it pointed to: the outside of a closed mesh stays
// outside under mirroring, as for a mesh flattened with its winding reversed.
PT_HDI vec3 NormalToWorld(const Instance& inst, vec3 n) {
  vec3 w = inst.toObject.TransposedVector(n);
  float len2 = glm::dot(w, w);
  return len2 > 0.0f ? w * (1.0f / sqrtf(len2)) : n;
}

// The surface found in object space, placed in the world: point and error bounds, normals
// (the shading normal turned back onto the geometric one's side, which a non-uniform scale
// may have crossed) and the instance's material override.
PT_HDI void InstanceToWorld(const Instance& inst, SurfaceInteraction* si) {
  if (inst.material >= 0) si->material = uint32_t(inst.material);
  if (inst.flags & kInstanceIdentity) return;
  PointToWorld(inst.toWorld, &si->p, &si->pError);
  si->ng = NormalToWorld(inst, si->ng);
  vec3 ns = NormalToWorld(inst, si->ns);
  si->ns = glm::dot(ns, si->ng) < 0.0f ? -ns : ns;
}

// The light of an instance's triangle (index `triangle` in triangles): the placement's own area
// lights start at lightBase, one per emitting triangle in the order PrimRef::light numbers the
// mesh's emitters - or, when an emissive override makes every triangle emit, in the mesh's
// triangle order. The world's primitives are the identity instance with lightBase 0, so their
// PrimRef::light is their light.
PT_HDI int32_t InstanceLight(const Instance& inst, int32_t primLight, uint32_t triangle) {
  if (inst.lightBase < 0) return -1;
  if (inst.material >= 0) return inst.lightBase + int32_t(triangle - inst.firstTriangle);
  return primLight < 0 ? -1 : inst.lightBase + primLight;
}

// An instanced triangle in world space, wound so that its cross product is the front normal
// NormalToWorld gives (mirroring swaps two vertices). For light sampling.
PT_HDI Triangle TriangleToWorld(const Instance& inst, const Triangle& t) {
  if (inst.flags & kInstanceIdentity) return t;
  vec3 p0 = inst.toWorld.Point(t.p0), p1 = inst.toWorld.Point(t.p1),
       p2 = inst.toWorld.Point(t.p2);
  if (inst.flags & kInstanceMirrored) return Triangle{p0, p2, p1};
  return Triangle{p0, p1, p2};
}

}  // namespace pt
