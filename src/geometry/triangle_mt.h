// Moller-Trumbore ray-triangle intersection (1997): the common fast test, kept only for the
// robustness study (--tri-test mt). Unlike the watertight test it computes barycentrics from
// rounded cross products with no consistent edge rule, so rays through shared edges can slip
// between two triangles; the study measures how often and what it saves.
#pragma once

#include "src/core/ray.h"
#include "src/scene/scene_types.h"

namespace pt {

PT_HDI bool IntersectTriangleMollerTrumbore(const Triangle& tri, const Ray& ray, float tMax,
                                            float* tHit, vec2* bary) {
  vec3 e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  vec3 pv = glm::cross(ray.d, e2);
  float det = glm::dot(e1, pv);
  if (det == 0.0f) return false;  // the ray lies in the triangle's plane
  float invDet = 1.0f / det;
  vec3 tv = ray.o - tri.p0;
  float u = glm::dot(tv, pv) * invDet;
  if (u < 0.0f || u > 1.0f) return false;
  vec3 qv = glm::cross(tv, e1);
  float v = glm::dot(ray.d, qv) * invDet;
  if (v < 0.0f || u + v > 1.0f) return false;
  float t = glm::dot(e2, qv) * invDet;
  if (!(t > 0.0f && t < tMax)) return false;
  *tHit = t;
  *bary = vec2(u, v);
  return true;
}

}  // namespace pt
