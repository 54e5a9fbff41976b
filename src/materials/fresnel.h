// Fresnel reflectance and Snell refraction, shared by every BSDF lobe (smooth now, GGX later).
// Conventions follow pbrt-v4: directions point away from the surface, eta is the relative
// index of refraction (inside / outside) and a negative cosine means "arriving from inside".
#pragma once

#include "src/core/math.h"

namespace pt {

// Mirror image of wo about the unit normal n (both pointing away from the surface).
PT_HDI vec3 Reflect(vec3 wo, vec3 n) { return -wo + 2.0f * glm::dot(wo, n) * n; }

// Exact unpolarised reflectance of a smooth dielectric interface: the mean of the s- and
// p-polarised Fresnel terms. cosThetaI < 0 means the ray arrives from inside, so the relative
// index becomes 1 / eta (pbrt-v4 FrDielectric). Returns 1 under total internal reflection.
PT_HDI float FresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = fminf(fmaxf(cosThetaI, -1.0f), 1.0f);
  if (cosThetaI < 0.0f) {
    eta = 1.0f / eta;
    cosThetaI = -cosThetaI;
  }
  float sin2ThetaI = fmaxf(0.0f, 1.0f - cosThetaI * cosThetaI);
  float sin2ThetaT = sin2ThetaI / (eta * eta);
  if (sin2ThetaT >= 1.0f) return 1.0f;
  float cosThetaT = SafeSqrt(1.0f - sin2ThetaT);
  float rParl = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
  float rPerp = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
  return 0.5f * (rParl * rParl + rPerp * rPerp);
}

// Schlick's approximation with per-channel normal-incidence reflectance f0. |cosTheta| is used,
// so a two-sided lobe may pass the cosine of either side.
PT_HDI vec3 FresnelSchlick(vec3 f0, float cosTheta) {
  float m = Clamp01(1.0f - fabsf(cosTheta));
  float m5 = (m * m) * (m * m) * m;
  return f0 + (vec3(1.0f) - f0) * m5;
}

// Refracts wi (pointing away from the surface) through the interface with normal n and
// relative index eta (pbrt-v4 Refract). When wi is on the side opposite n the interface is
// crossed from inside: eta is inverted and n flipped. *etap receives the relative index that
// was actually crossed; returns false under total internal reflection.
PT_HDI bool Refract(vec3 wi, vec3 n, float eta, float* etap, vec3* wt) {
  float cosThetaI = glm::dot(n, wi);
  if (cosThetaI < 0.0f) {
    eta = 1.0f / eta;
    cosThetaI = -cosThetaI;
    n = -n;
  }
  float sin2ThetaI = fmaxf(0.0f, 1.0f - cosThetaI * cosThetaI);
  float sin2ThetaT = sin2ThetaI / (eta * eta);
  if (sin2ThetaT >= 1.0f) return false;
  float cosThetaT = SafeSqrt(1.0f - sin2ThetaT);
  *wt = -wi / eta + (cosThetaI / eta - cosThetaT) * n;
  if (etap) *etap = eta;
  return true;
}

}  // namespace pt
