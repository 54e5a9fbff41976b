// The shading normal a vertex shades with, bent where it disagrees with the geometry so badly
// that the viewer is (nearly) below its hemisphere.
//
// Interpolated and normal-mapped normals can face away from a viewer that the triangle faces.
// Every lobe then works in the wrong hemisphere, and the shade stage, which never lets a ray
// cross the geometric surface the wrong way (GeometricallyConsistent), keeps only the thin
// wedge between the two surfaces: the pixel goes black. The chosen fix is Cycles' "ensure valid
// specular reflection": rotate the shading normal towards the geometric normal, in the plane
// the two span, just far enough that the mirror reflection of the view direction lies above
// the geometric surface (at least min(0.9 cos, 0.01) above it, cos the view's own elevation).
// The view is then inside the bent normal's hemisphere, so every lobe, of every material,
// samples and evaluates on the viewer's side, and the geometric check still stops any leak.
// A normal whose reflection is already valid is returned unchanged (bit for bit), and so is a
// flat-shaded one: scenes without shading normals render exactly as before.
//
// The alternative, microfacet-based normal mapping (Schuessler et al. 2017), conserves energy
// exactly but needs a second facet and a random walk in every lobe; the bend costs a few
// instructions once per vertex. What the bend still loses (diffuse directions between the
// bent normal's horizon and the geometric one) is measured in tests/shading_normals_test.cpp.
#pragma once

#include "src/core/math.h"
#include "src/geometry/interaction.h"

namespace pt {

// ng: unit geometric normal and ns: unit shading normal, both on wo's side (dot(wo, ng) > 0,
// dot(ns, ng) >= 0). Returns ns, or the unit normal in the plane of ns and ng closest to ns
// whose mirror reflection of wo has the required elevation over the geometric surface.
PT_HDI vec3 BendForValidReflection(vec3 ng, vec3 wo, vec3 ns) {
  const float cosO = glm::dot(wo, ng);
  if (!(cosO > 0.0f)) return ns;  // grazing or degenerate: nothing to bend towards
  const float threshold = fminf(0.9f * cosO, 0.01f);
  const vec3 reflected = 2.0f * glm::dot(ns, wo) * ns - wo;
  if (glm::dot(reflected, ng) >= threshold) return ns;
  // Local frame: z = ng, x = the part of ns tangent to the surface; the bent normal is
  // (nx, 0, nz). Its reflection of wo has elevation t when 2 (nx ox + nz cosO) nz - cosO = t;
  // squared, a quadratic in s = nz^2: 4 a s^2 - 2 b s + c = 0 with a, b, c below. Of its two
  // roots, the one where both sides of the unsquared equation share the sign of ox is valid.
  vec3 x = ns - glm::dot(ns, ng) * ng;
  const float xLen2 = glm::dot(x, x);
  if (!(xLen2 > 0.0f)) return ng;
  x *= 1.0f / sqrtf(xLen2);
  const float ox = glm::dot(wo, x);
  const float a = ox * ox + cosO * cosO;
  const float b = 2.0f * (a + cosO * threshold);
  const float c = Sqr(threshold + cosO);
  const float root = sqrtf(fmaxf(b * b - 4.0f * a * c, 0.0f));
  const float s = fminf(fmaxf(0.25f * (ox < 0.0f ? b + root : b - root) / a, 0.0f), 1.0f);
  const vec3 bent = sqrtf(1.0f - s) * x + sqrtf(s) * ng;
  return glm::normalize(bent);
}

// The shading normal for a vertex seen along wo (unit, pointing away from the surface), kept on
// ng's side as SurfaceInteraction::ns is. Flat shading (ns == ng) passes through untouched.
PT_HDI vec3 ViewValidShadingNormal(const SurfaceInteraction& si, vec3 wo) {
  if (si.ns.x == si.ng.x && si.ns.y == si.ng.y && si.ns.z == si.ng.z) return si.ns;
  const float side = glm::dot(wo, si.ng) < 0.0f ? -1.0f : 1.0f;
  return side * BendForValidReflection(side * si.ng, wo, side * si.ns);
}

}  // namespace pt
