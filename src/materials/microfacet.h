// The GGX (Trowbridge-Reitz) microfacet distribution, isotropic, in the local shading frame
// (z = shading normal), as pbrt-v4's TrowbridgeReitzDistribution: normal distribution D,
// height-correlated Smith masking-shadowing G, and sampling of the distribution of visible
// normals (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"), whose density
// D_w(wm) = G1(w) max(0, w.wm) D(wm) / |cos w| makes the sample weights of the rough lobes
// bounded by G / G1 <= 1 (no fireflies from the distribution itself).
#pragma once

#include "src/core/math.h"

namespace pt {

// GGX alpha = roughness^2 (glTF). Below kSmoothAlpha a lobe is a perfect mirror (pbrt-v4's
// EffectivelySmooth): D would be too peaked for float and for light sampling to ever hit it.
constexpr float kSmoothAlpha = 1e-3f;

PT_HDI float GgxAlpha(float roughness) { return roughness * roughness; }
PT_HDI bool IsEffectivelySmooth(float roughness) { return GgxAlpha(roughness) < kSmoothAlpha; }

// Half vector of a reflection pair on the same side (wo.z, wi.z > 0); false when degenerate.
PT_HDI bool ReflectionHalfVector(vec3 wo, vec3 wi, vec3* wm) {
  vec3 h = wo + wi;
  float lenSq = glm::dot(h, h);
  if (lenSq == 0.0f) return false;
  *wm = h / sqrtf(lenSq);
  return true;
}

struct GgxDistribution {
  float alpha;

  // Density of microfacet normals per unit projected area: alpha^2 / (pi (alpha^2 cos^2 +
  // sin^2)^2), with sin^2 taken from the tangential components (1 - cos^2 would cancel
  // catastrophically at small alpha). Even in wm.z; wm is a unit vector.
  PT_HDI float D(vec3 wm) const {
    float a2 = alpha * alpha;
    float sin2 = wm.x * wm.x + wm.y * wm.y;
    float denom = a2 * wm.z * wm.z + sin2;
    if (denom <= 0.0f) return 0.0f;
    return a2 / (kPi * denom * denom);
  }

  // Smith's Lambda: (sqrt(1 + alpha^2 tan^2) - 1) / 2, written without the cancellation at
  // small alpha tan. Infinite at grazing (fully masked).
  PT_HDI float Lambda(vec3 w) const {
    float cosT = fabsf(w.z);
    if (cosT == 0.0f) return kInfinity;
    float a2s2 = alpha * alpha * (w.x * w.x + w.y * w.y);
    return a2s2 / (2.0f * cosT * (sqrtf(cosT * cosT + a2s2) + cosT));
  }

  PT_HDI float G1(vec3 w) const { return 1.0f / (1.0f + Lambda(w)); }

  // Height-correlated masking-shadowing of the pair.
  PT_HDI float G(vec3 wo, vec3 wi) const { return 1.0f / (1.0f + Lambda(wo) + Lambda(wi)); }

  // Distribution of upper-hemisphere normals visible from w: from below (w.z < 0) the same as
  // from -w. Integrates to 1 over wm.z > 0; zero for normals facing away.
  PT_HDI float VisibleD(vec3 w, vec3 wm) const {
    float cosT = fabsf(w.z);
    float cosM = copysignf(1.0f, w.z) * glm::dot(w, wm);
    if (cosT == 0.0f || cosM <= 0.0f) return 0.0f;
    return G1(w) / cosT * D(wm) * cosM;
  }

  // Draws wm (wm.z > 0) from VisibleD(w, .): Heitz 2018. Stretch w to the unit-roughness
  // configuration, sample the projected visible hemisphere there, unstretch.
  PT_HDI vec3 SampleVisibleNormal(vec3 w, vec2 u) const;

  // Solid-angle density of wi = Reflect(wo, wm) when wm ~ VisibleD(wo, .): the Jacobian of
  // the reflection map is 1 / (4 |wo.wm|).
  PT_HDI float ReflectionPdf(vec3 wo, vec3 wm) const {
    float cosOM = fabsf(glm::dot(wo, wm));
    return cosOM > 0.0f ? VisibleD(wo, wm) / (4.0f * cosOM) : 0.0f;
  }
};

PT_HDI vec3 GgxDistribution::SampleVisibleNormal(vec3 w, vec2 u) const {
  vec3 wh = glm::normalize(vec3(alpha * w.x, alpha * w.y, w.z));
  if (wh.z < 0.0f) wh = -wh;  // seen from below: the same normals as from -w
  float lenSq = wh.x * wh.x + wh.y * wh.y;
  vec3 t1 = lenSq > 0.0f ? vec3(-wh.y, wh.x, 0.0f) / sqrtf(lenSq) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = glm::cross(wh, t1);
  // Uniform point on the disk, its upper half squashed onto the projected hemisphere.
  float r = sqrtf(u.x);
  float phi = 2.0f * kPi * u.y;
  float p1 = r * cosf(phi), p2 = r * sinf(phi);
  float s = 0.5f * (1.0f + wh.z);
  p2 = (1.0f - s) * SafeSqrt(1.0f - p1 * p1) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + SafeSqrt(1.0f - p1 * p1 - p2 * p2) * wh;
  return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, fmaxf(1e-6f, nh.z)));
}

}  // namespace pt
