// Warping functions from the unit square to directions and points, with their pdfs.
#pragma once

#include "src/core/math.h"

namespace pt {

PT_HDI vec2 SampleUniformDiskConcentric(vec2 u) {
  vec2 o = 2.0f * u - vec2(1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return vec2(0.0f);
  float r, theta;
  if (fabsf(o.x) > fabsf(o.y)) {
    r = o.x;
    theta = (kPi / 4.0f) * (o.y / o.x);
  } else {
    r = o.y;
    theta = (kPi / 2.0f) - (kPi / 4.0f) * (o.x / o.y);
  }
  return r * vec2(cosf(theta), sinf(theta));
}

// Cosine-weighted direction about +z; pdf = cos(theta) / pi.
PT_HDI vec3 SampleCosineHemisphere(vec2 u) {
  vec2 d = SampleUniformDiskConcentric(u);
  float z = SafeSqrt(1.0f - d.x * d.x - d.y * d.y);
  return vec3(d.x, d.y, z);
}
PT_HDI float CosineHemispherePdf(float cosTheta) { return fmaxf(cosTheta, 0.0f) * kInvPi; }

PT_HDI vec3 SampleUniformSphere(vec2 u) {
  float z = 1.0f - 2.0f * u.x;
  float r = SafeSqrt(1.0f - z * z);
  float phi = 2.0f * kPi * u.y;
  return vec3(r * cosf(phi), r * sinf(phi), z);
}
PT_HDI float UniformSpherePdf() { return kInv4Pi; }

// Uniform direction in the cone of half-angle acos(cosMax) about +z.
PT_HDI vec3 SampleUniformCone(vec2 u, float cosMax) {
  float cosTheta = (1.0f - u.x) + u.x * cosMax;
  float sinTheta = SafeSqrt(1.0f - cosTheta * cosTheta);
  float phi = u.y * 2.0f * kPi;
  return vec3(cosf(phi) * sinTheta, sinf(phi) * sinTheta, cosTheta);
}
PT_HDI float UniformConePdf(float cosMax) { return 1.0f / (2.0f * kPi * (1.0f - cosMax)); }

// Uniform barycentrics over a triangle (Heitz 2019, low distortion).
PT_HDI vec2 SampleUniformTriangle(vec2 u) {
  float b0, b1;
  if (u.x < u.y) {
    b0 = u.x / 2.0f;
    b1 = u.y - b0;
  } else {
    b1 = u.y / 2.0f;
    b0 = u.x - b1;
  }
  return vec2(b0, b1);
}

PT_HDI float PowerHeuristic(float fPdf, float gPdf) {
  float f = fPdf * fPdf, g = gPdf * gPdf;
  if (isinf(f)) return 1.0f;
  return (f + g) > 0.0f ? f / (f + g) : 0.0f;
}

}  // namespace pt
