// The equirectangular environment map as a light (see EnvironmentView for the convention):
// nearest-texel lookup, and importance sampling by a piecewise-constant distribution over
// texels proportional to luminance x the texel's solid angle, uniform in solid angle inside
// the chosen texel. The radiance is constant over a texel and so is the pdf, so the pdf is
// exactly proportional to the luminance that is evaluated: a texel of zero radiance has pdf 0
// and is never sampled, and a BSDF-sampled ray that escapes evaluates the same pdf (MIS).
// With EnvironmentView::uniformSampling the sphere is sampled uniformly instead (a study).
#pragma once

#include "src/core/sampling.h"
#include "src/scene/scene_view.h"

namespace pt {

struct EnvTexel {
  uint32_t i, j;  // column, row (row 0 at the top: +Y)
};

// Largest k in [0, n) with cdf[k] <= u: an interval of zero width is never chosen.
PT_HDI uint32_t SampleCdf(const float* cdf, uint32_t n, float u) {
  uint32_t lo = 0, hi = n - 1;
  while (lo < hi) {
    uint32_t mid = (lo + hi + 1) / 2;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// cos(theta_j) - cos(theta_j+1) of row j, as 2 sin(mid) sin(half-width): no cancellation near
// the poles, where the direct difference of two cosines close to +-1 would lose every digit.
PT_HDI float EnvRowCosWidth(uint32_t j, uint32_t height) {
  float halfWidth = 0.5f * kPi / float(height);
  return 2.0f * sinf(kPi * (float(j) + 0.5f) / float(height)) * sinf(halfWidth);
}

// Solid angle of any texel of row j.
PT_HDI float EnvTexelSolidAngle(uint32_t j, uint32_t width, uint32_t height) {
  return EnvRowCosWidth(j, height) * (2.0f * kPi / float(width));
}

// The texel a world direction falls in (nearest lookup).
PT_HDI EnvTexel EnvTexelOf(const EnvironmentView& e, vec3 w) {
  vec3 d = e.toLocal * w;
  float theta = atan2f(sqrtf(d.x * d.x + d.z * d.z), d.y);  // accurate at the poles too
  float u = 0.5f + atan2f(d.x, -d.z) * (0.5f * kInvPi);
  uint32_t j = uint32_t(fminf(fmaxf(theta * kInvPi * float(e.height), 0.0f), float(e.height - 1)));
  uint32_t i = uint32_t(fminf(fmaxf(u * float(e.width), 0.0f), float(e.width - 1)));
  return {i, j};
}

PT_HDI vec3 EnvTexelRadiance(const SceneView& s, EnvTexel t) {
  return s.env.strength * s.envTexels[size_t(t.j) * s.env.width + t.i];
}

// Solid-angle pdf of importance sampling texel t: P(row) P(column | row) / solid angle, the
// probabilities being the widths of the cdf intervals the sampler draws from.
PT_HDI float EnvTexelPdf(const SceneView& s, EnvTexel t) {
  uint32_t w = s.env.width;
  float pRow = s.envRowCdf[t.j + 1] - s.envRowCdf[t.j];
  const float* column = s.envColumnCdf + size_t(t.j) * (w + 1);
  float pColumn = column[t.i + 1] - column[t.i];
  float pdf = pRow * pColumn / EnvTexelSolidAngle(t.j, w, s.env.height);
  return pdf < kInfinity ? pdf : 0.0f;
}

// Radiance arriving along the escaped direction w (world, unit).
PT_HDI vec3 EnvMapLe(const SceneView& s, vec3 w) {
  return EnvTexelRadiance(s, EnvTexelOf(s.env, w));
}

// Solid-angle pdf (without the light-choice probability) that SampleEnvMap returns w.
PT_HDI float EnvMapPdf(const SceneView& s, vec3 w) {
  if (s.env.uniformSampling) return UniformSpherePdf();
  return EnvTexelPdf(s, EnvTexelOf(s.env, w));
}

// A direction uniform in solid angle inside texel t; (a, b) in [0, 1)^2 across its column and
// row. cos(theta) runs linearly across the row; 1 - cos and 1 + cos are each built from
// non-negative parts, so sin(theta) stays accurate next to either pole.
PT_HDI vec3 EnvTexelDirection(const EnvironmentView& e, EnvTexel t, float a, float b) {
  float thetaTop = kPi * float(t.j) / float(e.height);
  float thetaBottom = kPi * float(t.j + 1) / float(e.height);
  float width = EnvRowCosWidth(t.j, e.height);
  float oneMinusZ = 2.0f * Sqr(sinf(0.5f * thetaTop)) + b * width;
  float onePlusZ = 2.0f * Sqr(cosf(0.5f * thetaBottom)) + (1.0f - b) * width;
  float z = oneMinusZ < onePlusZ ? 1.0f - oneMinusZ : onePlusZ - 1.0f;
  float sinTheta = SafeSqrt(oneMinusZ * onePlusZ);
  float phi = 2.0f * kPi * ((float(t.i) + a) / float(e.width) - 0.5f);
  vec3 d(sinTheta * sinf(phi), z, -sinTheta * cosf(phi));
  return glm::normalize(e.toWorld * d);
}

// Samples a direction towards the map: *w (world), the radiance *L along it and its
// solid-angle *pdf (without the light choice). False when nothing can be sampled.
PT_HDI bool SampleEnvMap(const SceneView& s, vec2 u, vec3* w, vec3* L, float* pdf) {
  if (s.env.uniformSampling) {
    *w = SampleUniformSphere(u);
    *L = EnvMapLe(s, *w);
    *pdf = UniformSpherePdf();
    return true;
  }
  uint32_t width = s.env.width;
  EnvTexel t;
  t.j = SampleCdf(s.envRowCdf, s.env.height, u.x);
  const float* column = s.envColumnCdf + size_t(t.j) * (width + 1);
  t.i = SampleCdf(column, width, u.y);
  // What is left of each uniform number inside its interval places the point in the texel.
  float pRow = s.envRowCdf[t.j + 1] - s.envRowCdf[t.j];
  float pColumn = column[t.i + 1] - column[t.i];
  if (!(pRow > 0.0f) || !(pColumn > 0.0f)) return false;
  float b = fminf((u.x - s.envRowCdf[t.j]) / pRow, 0x1.fffffep-1f);
  float a = fminf((u.y - column[t.i]) / pColumn, 0x1.fffffep-1f);
  *w = EnvTexelDirection(s.env, t, a, b);
  *L = EnvTexelRadiance(s, t);
  *pdf = EnvTexelPdf(s, t);
  return *pdf > 0.0f;
}

}  // namespace pt
