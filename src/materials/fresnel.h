// Fresnel reflectance and Snell refraction, and the sample record and hemisphere helpers that
// every BSDF lobe shares (here, so that bsdf.h and plastic.h both include them without a
// cycle). Conventions follow pbrt-v4: directions point away from the surface, eta is the
// relative index of refraction (inside / outside) and a negative cosine means "arriving from
// inside".
#pragma once

#include "src/core/math.h"

namespace pt {

// One sampled direction. f excludes the cosine; pdf is per unit solid angle for non-delta
// lobes and the discrete probability of the lobe for a delta one, so that f |cos wi| / pdf is
// always the path weight.
struct BsdfSample {
  vec3 f = vec3(0.0f);
  vec3 wi = vec3(0.0f);
  float pdf = 0.0f;
  bool isDelta = false;
  bool isTransmission = false;
  float eta = 1.0f;  // relative index crossed (pbrt's etap): 1 for reflection
  // A thin wall's transmission: crosses the surface but enters no medium (the path's medium
  // stays what it was).
  bool passesThrough = false;
};

PT_HDI float AbsCosTheta(vec3 w) { return fabsf(w.z); }
PT_HDI bool SameHemisphere(vec3 a, vec3 b) { return a.z * b.z > 0.0f; }
// Mirror image in the tangent plane: two-sided lobes evaluate the back face as the front.
PT_HDI vec3 FlipZ(vec3 w) { return vec3(w.x, w.y, -w.z); }

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

// Fdr for a relative index n >= 1: the closed form of 2 * integral of F(mu) mu dmu (as in
// d'Eon's "A Hitchhiker's Guide to Multiple Scattering"), accurate to ~3e-6 in float for
// n >= 1.05. Closer to 1 its terms cancel, so d'Eon and Irving's fit (used by Mitsuba) takes
// over there; its absolute error is below 2e-4 where Fdr itself is below 0.014. Indices
// beyond 1e3 (Fdr > 0.99) are clamped so that n^8 stays finite in float.
PT_HDI float FresnelDiffuseReflectanceAbove1(float n) {
  n = fminf(n, 1e3f);
  if (n < 1.05f) {
    float x = 1.0f / n;
    return 0.919317f +
           x * (-3.4793f + x * (6.75335f + x * (-7.80989f + x * (4.98554f + x * -1.36881f))));
  }
  float n2 = n * n, n4 = n2 * n2;
  float a = (n - 1.0f) * (3.0f * n + 1.0f) / (6.0f * Sqr(n + 1.0f));
  float b = n2 * Sqr(n2 - 1.0f) / (n2 + 1.0f) / Sqr(n2 + 1.0f) * logf((n - 1.0f) / (n + 1.0f));
  float c = 2.0f * n * n2 * (n2 + 2.0f * n - 1.0f) / ((n2 + 1.0f) * (n4 - 1.0f));
  float d = 8.0f * n4 * (n4 + 1.0f) / ((n2 + 1.0f) * Sqr(n4 - 1.0f)) * logf(n);
  return 0.5f + a + b - c + d;
}

// Diffuse Fresnel reflectance "Fdr" (Mitsuba's fresnel_diffuse_reflectance): the fraction of
// uniform (cosine-weighted) illumination that a smooth interface of relative index eta
// reflects. For eta < 1 (from the denser side) it follows from eta > 1 by reciprocity of the
// transmitted fraction, 1 - Fdr(eta) = eta^2 (1 - Fdr(1 / eta)), exactly; so a layer that
// weights its inside by 1 / (1 - Fdr(1 / eta)) conserves energy by construction.
PT_HDI float FresnelDiffuseReflectance(float eta) {
  if (eta >= 1.0f) return FresnelDiffuseReflectanceAbove1(eta);
  return 1.0f - eta * eta * (1.0f - FresnelDiffuseReflectanceAbove1(1.0f / eta));
}

}  // namespace pt
