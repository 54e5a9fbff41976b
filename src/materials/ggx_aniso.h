// Anisotropic GGX (KHR_materials_anisotropy) in the local shading frame: alphaT along the
// anisotropy direction t = (c, s, 0), alphaB across it. The distribution, Smith's Lambda and the
// visible-normal sampling are microfacet.h's with the tangential components scaled per axis
// (Heitz 2014, "Understanding the Masking-Shadowing Function"; Heitz 2018 for the sampling,
// which stretches by (alphaT, alphaB)); alphaT = alphaB is exactly the isotropic lobe.
#pragma once

#include "src/materials/microfacet.h"

namespace pt {

struct AnisoGgx {
  float alphaT = 1.0f, alphaB = 1.0f;
  float c = 1.0f, s = 0.0f;  // the anisotropy direction in the local frame

  PT_HDI static AnisoGgx Isotropic(float alpha) { return AnisoGgx{alpha, alpha, 1.0f, 0.0f}; }

  // A mirror when both alphas are (pbrt-v4's EffectivelySmooth).
  PT_HDI bool Smooth() const { return fmaxf(alphaT, alphaB) < kSmoothAlpha; }

  // Into the frame whose x is the anisotropy direction, and back.
  PT_HDI vec3 ToAniso(vec3 w) const { return vec3(c * w.x + s * w.y, -s * w.x + c * w.y, w.z); }
  PT_HDI vec3 FromAniso(vec3 w) const { return vec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z); }

  // 1 / (pi aT aB ((m.t / aT)^2 + (m.b / aB)^2 + m.n^2)^2) for a unit normal m.
  PT_HDI float D(vec3 wm) const {
    vec3 m = ToAniso(wm);
    float e = Sqr(m.x / alphaT) + Sqr(m.y / alphaB) + m.z * m.z;
    if (!(e > 0.0f)) return 0.0f;
    return 1.0f / (kPi * alphaT * alphaB * e * e);
  }

  PT_HDI float Lambda(vec3 w) const {
    float cosT = fabsf(w.z);
    if (cosT == 0.0f) return kInfinity;
    vec3 a = ToAniso(w);
    float a2s2 = Sqr(alphaT * a.x) + Sqr(alphaB * a.y);
    return a2s2 / (2.0f * cosT * (sqrtf(cosT * cosT + a2s2) + cosT));
  }

  PT_HDI float G1(vec3 w) const { return 1.0f / (1.0f + Lambda(w)); }
  PT_HDI float G(vec3 wo, vec3 wi) const { return 1.0f / (1.0f + Lambda(wo) + Lambda(wi)); }

  PT_HDI float VisibleD(vec3 w, vec3 wm) const {
    float cosT = fabsf(w.z);
    float cosM = copysignf(1.0f, w.z) * glm::dot(w, wm);
    if (cosT == 0.0f || cosM <= 0.0f) return 0.0f;
    return G1(w) / cosT * D(wm) * cosM;
  }

  PT_HDI float ReflectionPdf(vec3 wo, vec3 wm) const {
    float cosOM = fabsf(glm::dot(wo, wm));
    return cosOM > 0.0f ? VisibleD(wo, wm) / (4.0f * cosOM) : 0.0f;
  }

  // GGX reflection D G / (4 cos_o cos_i) without Fresnel, for wo, wi above the surface.
  PT_HDI float Reflection(vec3 wo, vec3 wi, vec3* wm) const {
    if (wo.z <= 0.0f || wi.z <= 0.0f || !ReflectionHalfVector(wo, wi, wm)) return 0.0f;
    return D(*wm) * G(wo, wi) / (4.0f * wo.z * wi.z);
  }

  PT_HDI vec3 SampleVisibleNormal(vec3 w, vec2 u) const {
    vec3 a = ToAniso(w);
    vec3 wh = glm::normalize(vec3(alphaT * a.x, alphaB * a.y, a.z));
    if (wh.z < 0.0f) wh = -wh;
    float lenSq = wh.x * wh.x + wh.y * wh.y;
    vec3 t1 = lenSq > 0.0f ? vec3(-wh.y, wh.x, 0.0f) / sqrtf(lenSq) : vec3(1.0f, 0.0f, 0.0f);
    vec3 t2 = glm::cross(wh, t1);
    float r = sqrtf(u.x);
    float phi = 2.0f * kPi * u.y;
    float p1 = r * cosf(phi), p2 = r * sinf(phi);
    float h = 0.5f * (1.0f + wh.z);
    p2 = (1.0f - h) * SafeSqrt(1.0f - p1 * p1) + h * p2;
    vec3 nh = p1 * t1 + p2 * t2 + SafeSqrt(1.0f - p1 * p1 - p2 * p2) * wh;
    return FromAniso(glm::normalize(vec3(alphaT * nh.x, alphaB * nh.y, fmaxf(1e-6f, nh.z))));
  }
};

}  // namespace pt
