// The sheen lobe of KHR_materials_sheen in the local shading frame (z = shading normal): the
// "Charlie" distribution of fibre normals with its visibility term (Conty and Kulla 2017,
// "Production Friendly Microfacet Sheen BRDF"), exactly the extension's formulas:
//
//   D(h)   = (2 + 1 / alpha) sin(theta_h)^(1 / alpha) / (2 pi),   alpha = sheenRoughness^2
//   V      = 1 / ((1 + Lambda(mu_o) + Lambda(mu_i)) 4 mu_o mu_i)   (Lambda: their fitted curve)
//   f      = sheenColor D(h) V                                     (symmetric: reciprocal)
//
// Sampling: D(h) cos(theta_h) is a normalised density of fibre normals, with the closed-form
// inverse sin(theta_h) = u^(alpha / (2 alpha + 1)); the reflection of wo about h has solid-angle
// density D(h) cos(theta_h) / (4 |wo.h|). Normals that reflect wo below the horizon are the
// density's missing mass (the sample fails). Its albedo (for a white sheen colour) is tabulated
// in sheen_albedo_table.h (tools/make_layer_tables.cpp), which scales the layers below it.
#pragma once

#include "src/core/math.h"
#include "src/materials/microfacet.h"

namespace pt {

// Below this alpha the distribution's exponent 1 / alpha underflows float powers of sin^2 and
// the lobe is a sliver at grazing angles that nothing samples: sheen roughness is clamped to
// sqrt(kMinSheenAlpha) = 0.07.
constexpr float kMinSheenAlpha = 0.0049f;

struct CharlieSheen {
  float alpha;

  PT_HDI static CharlieSheen FromRoughness(float roughness) {
    return CharlieSheen{fmaxf(Sqr(Clamp01(roughness)), kMinSheenAlpha)};
  }

  // Density of fibre normals (even in wm.z); wm is a unit vector.
  PT_HDI float D(vec3 wm) const {
    float invR = 1.0f / alpha;
    float sin2 = fminf(wm.x * wm.x + wm.y * wm.y, 1.0f);
    return (2.0f + invR) * powf(sin2, 0.5f * invR) * (0.5f * kInvPi);
  }

  // The fitted exponent of Lambda (Conty and Kulla, interpolated in (1 - alpha)^2).
  PT_HDI float L(float x) const {
    float t = Sqr(1.0f - alpha);
    float a = 21.5473f + (25.3245f - 21.5473f) * t;
    float b = 3.82987f + (3.32435f - 3.82987f) * t;
    float c = 0.19823f + (0.16801f - 0.19823f) * t;
    float d = -1.97760f + (-1.27393f + 1.97760f) * t;
    float e = -4.32054f + (-4.85967f + 4.32054f) * t;
    return a / (1.0f + b * powf(x, c)) + d * x + e;
  }

  PT_HDI float Lambda(float cosTheta) const {
    float c = fabsf(cosTheta);
    return c < 0.5f ? expf(L(c)) : expf(2.0f * L(0.5f) - L(1.0f - c));
  }

  // D V for a pair above the surface (wo.z, wi.z > 0); 0 otherwise.
  PT_HDI float Eval(vec3 wo, vec3 wi) const {
    vec3 wm;
    if (wo.z <= 0.0f || wi.z <= 0.0f || !ReflectionHalfVector(wo, wi, &wm)) return 0.0f;
    return D(wm) / ((1.0f + Lambda(wo.z) + Lambda(wi.z)) * (4.0f * wo.z * wi.z));
  }

  // A fibre normal with density D(wm) wm.z over the upper hemisphere.
  PT_HDI vec3 SampleNormal(vec2 u) const {
    float sinT = powf(u.x, alpha / (2.0f * alpha + 1.0f));
    float cosT = SafeSqrt(1.0f - sinT * sinT);
    float phi = 2.0f * kPi * u.y;
    return vec3(sinT * cosf(phi), sinT * sinf(phi), cosT);
  }

  // Solid-angle density of wi = Reflect(wo, wm) for that sampling (wo, wi above the surface).
  PT_HDI float ReflectionPdf(vec3 wo, vec3 wi) const {
    vec3 wm;
    if (wo.z <= 0.0f || wi.z <= 0.0f || !ReflectionHalfVector(wo, wi, &wm)) return 0.0f;
    float cosOM = glm::dot(wo, wm);
    return cosOM > 0.0f ? D(wm) * wm.z / (4.0f * cosOM) : 0.0f;
  }
};

}  // namespace pt
