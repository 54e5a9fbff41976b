// The thin-film Fresnel of KHR_materials_iridescence (Belcour and Barla 2017, "A Practical
// Extension to Microfacet Theory for the Modeling of Varying Iridescence"), as the extension
// specifies it: air / film (iridescenceIor, thickness d in nm) / base (its ior from F0), each
// interface's reflectance by Schlick's approximation, the Airy summation of the film's
// inter-reflections written as a Fourier series over the optical path difference
// OPD = 2 n_film d cos(theta_2), integrated against the CIE XYZ sensitivities analytically (their
// Gaussian fit, orders m = 1, 2) and converted to linear Rec. 709 RGB.
#pragma once

#include "src/core/math.h"

namespace pt {

PT_HDI float IorToF0(float transmitted, float incident) {
  return Sqr((transmitted - incident) / (transmitted + incident));
}

// The index whose normal-incidence reflectance from air is f0 (dielectric; for a metal the
// extension uses the same relation, extinction taken as 0).
PT_HDI vec3 F0ToIor(vec3 f0) {
  vec3 s = glm::sqrt(glm::clamp(f0, vec3(0.0f), vec3(0.9999f)));
  return (vec3(1.0f) + s) / (vec3(1.0f) - s);
}

// The spectral integral of one Fourier term cos(2 pi OPD / lambda + shift) against the XYZ
// sensitivities, in Rec. 709 RGB (the extension's evalSensitivity; opd in nm).
PT_HDI vec3 ThinFilmSensitivity(float opd, vec3 shift) {
  float phase = 2.0f * kPi * opd * 1.0e-9f;
  const vec3 val(5.4856e-13f, 4.4201e-13f, 5.2481e-13f);
  const vec3 pos(1.6810e+06f, 1.7953e+06f, 2.2084e+06f);
  const vec3 var(4.3278e+09f, 9.3046e+09f, 6.6121e+09f);
  vec3 xyz;
  for (int c = 0; c < 3; ++c)
    xyz[c] = val[c] * sqrtf(2.0f * kPi * var[c]) * cosf(pos[c] * phase + shift[c]) *
             expf(-phase * phase * var[c]);
  xyz.x += 9.7470e-14f * sqrtf(2.0f * kPi * 4.5282e+09f) * cosf(2.2399e+06f * phase + shift.x) *
           expf(-4.5282e+09f * phase * phase);
  xyz /= 1.0685e-7f;
  return vec3(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
              -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
              0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z);
}

// Reflectance (RGB) of the film over a base of normal-incidence reflectance baseF0, seen from
// air at cosine cosTheta1. thicknessNm 0 leaves the base's Schlick reflectance (the film's
// index blends to air's over the first 0.03 nm, as the Khronos sample viewer does).
PT_HDI vec3 ThinFilmFresnel(float filmIor, float thicknessNm, vec3 baseF0, float cosTheta1) {
  float t = Clamp01(thicknessNm / 0.03f);
  float n2 = 1.0f + (filmIor - 1.0f) * (t * t * (3.0f - 2.0f * t));
  cosTheta1 = Clamp01(cosTheta1);
  float cos2Sq = 1.0f - Sqr(1.0f / n2) * (1.0f - cosTheta1 * cosTheta1);
  if (cos2Sq < 0.0f) return vec3(1.0f);  // total internal reflection (film below air's index)
  float cosTheta2 = sqrtf(cos2Sq);
  // Air / film.
  float r0 = IorToF0(n2, 1.0f);
  float m1 = 1.0f - cosTheta1;
  float r12 = r0 + (1.0f - r0) * (m1 * m1) * (m1 * m1) * m1;
  float t121 = 1.0f - r12;
  float phi12 = n2 < 1.0f ? kPi : 0.0f;
  float phi21 = kPi - phi12;
  // Film / base.
  vec3 baseIor = F0ToIor(baseF0 + vec3(0.0001f));
  vec3 phi23(0.0f);
  float m2 = 1.0f - cosTheta2;
  float s2 = (m2 * m2) * (m2 * m2) * m2;
  vec3 r23;
  for (int c = 0; c < 3; ++c) {
    float r1 = IorToF0(baseIor[c], n2);
    r23[c] = r1 + (1.0f - r1) * s2;
    if (baseIor[c] < n2) phi23[c] = kPi;
  }
  float opd = 2.0f * n2 * thicknessNm * cosTheta2;
  vec3 phi = vec3(phi21) + phi23;
  // The Airy sum's Fourier series: DC term, then orders 1 and 2.
  vec3 r123 = glm::clamp(r12 * r23, vec3(1e-5f), vec3(0.9999f));
  vec3 sqrtR123 = glm::sqrt(r123);
  vec3 rs = (t121 * t121) * r23 / (vec3(1.0f) - r123);
  vec3 result = vec3(r12) + rs;
  vec3 cm = rs - vec3(t121);
  for (int m = 1; m <= 2; ++m) {
    cm *= sqrtR123;
    result += cm * 2.0f * ThinFilmSensitivity(float(m) * opd, float(m) * phi);
  }
  return glm::clamp(result, vec3(0.0f), vec3(1.0f));  // the series' truncation can pass 1
}

}  // namespace pt
