// A box object as six world-space parallelograms (host only: used by the scene loader).
#pragma once

#include <utility>
#include <vector>

#include "src/core/math.h"
#include "src/scene/scene_types.h"

namespace pt {

// Appends the six faces of the axis-aligned box [lo, hi] (object space) transformed by
// objectToWorld (affine; column-vector convention, translation in column 3). Each quad's
// cross(u, v) points out of the box; a transform with a negative determinant mirrors the
// faces, so u and v are swapped to keep the normals outward. Parallelograms map exactly to
// parallelograms under affine maps; corners are transformed in double and rounded once.
// Faces of zero area (a flat box) are skipped.
inline void AppendBoxQuads(vec3 lo, vec3 hi, const glm::mat4& objectToWorld,
                           std::vector<Quad>& out) {
  glm::dmat4 m(objectToWorld);
  glm::dvec3 dlo(lo), dhi(hi), size = dhi - dlo;
  bool mirrored = glm::determinant(glm::dmat3(m)) < 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    int b = (axis + 1) % 3, c = (axis + 2) % 3;
    glm::dvec3 eb(0.0), ec(0.0);
    eb[b] = size[b];
    ec[c] = size[c];
    for (int side = 0; side < 2; ++side) {
      glm::dvec3 origin = dlo;
      if (side == 1) origin[axis] = dhi[axis];
      // cross(e_b, e_c) = +e_axis for the cyclic order, so the +axis face uses (eb, ec).
      glm::dvec3 u = side == 1 ? eb : ec;
      glm::dvec3 v = side == 1 ? ec : eb;
      Quad q;
      q.origin = vec3(glm::dvec3(m * glm::dvec4(origin, 1.0)));
      q.u = vec3(glm::dvec3(m * glm::dvec4(u, 0.0)));
      q.v = vec3(glm::dvec3(m * glm::dvec4(v, 0.0)));
      if (mirrored) std::swap(q.u, q.v);
      vec3 n = glm::cross(q.u, q.v);
      float nn = glm::dot(n, n);  // zero for a flat face, inf when the face's size overflows
      if (!(nn > 0.0f) || !std::isfinite(nn) || !IsFinite(q.origin)) continue;
      out.push_back(q);
    }
  }
}

}  // namespace pt
