// Directional albedo of a BSDF's reflection, E(wo) = integral of f(wo, wi) |cos wi| over wi.z
// > 0, by deterministic quadrature of EvalBsdf (no sampling code involved): the white furnace
// tests' reference. Host-only.
#pragma once

#include <cmath>

#include "src/materials/bsdf.h"
#include "tests/stat_test_util.h"

namespace pt::test {

// 5-point Gauss-Legendre rule on [0, 1].
inline constexpr double kAlbedoGaussX[5] = {0.0469100770306680, 0.2307653449471585, 0.5,
                               0.7692346550528415, 0.9530899229693320};
inline constexpr double kAlbedoGaussW[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444,
                               0.2393143352496832, 0.1184634425280945};

// Directional albedo of the reflection (wi.z > 0) part of EvalBsdf for wo in the xz-plane, by
// the change of variables wi = Reflect(wo, wm), dwi = 4 |wo.wm| dwm: every wi above the
// horizon has exactly one half vector, on wm.z > 0 facing wo. The half vector's polar angle
// is tan(theta_m) = alpha tan(v), which spreads a GGX peak of width alpha evenly over v; phi
// runs over [0, pi] (the integrand is even in phi). Near the horizon G rises from 0 over a
// layer of wi.z ~ alpha, a curve across the (v, phi) cells, so the cells are refined
// adaptively (Gauss-Legendre 5 x 5, quartered until the quarters agree).
struct HalfVectorIntegrand {
  const Material& m;
  vec3 wo;
  double alpha;

  double operator()(double v, double phi) const {
    double thetaM = std::atan(alpha * std::tan(v));
    double dThetaDv = alpha / (std::pow(std::cos(v), 2) + std::pow(alpha * std::sin(v), 2));
    vec3 wm = SphericalToDirection(thetaM, phi);
    float cosOM = glm::dot(wo, wm);
    if (cosOM <= 0.0f) return 0.0;
    vec3 wi = Reflect(wo, wm);
    if (wi.z <= 0.0f) return 0.0;
    return double(EvalBsdf(m, wo, wi).x) * wi.z * 4.0 * cosOM * std::sin(thetaM) * dThetaDv;
  }
};

inline double IntegrateCell(const HalfVectorIntegrand& f, double v0, double p0, double dv, double dp) {
  double sum = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      sum += kAlbedoGaussW[i] * kAlbedoGaussW[j] * f(v0 + kAlbedoGaussX[i] * dv, p0 + kAlbedoGaussX[j] * dp);
  return sum * dv * dp;
}

inline double IntegrateAdaptive(const HalfVectorIntegrand& f, double v0, double p0, double dv,
                         double dp, double whole, double tol, int depth) {
  double part[4], sum = 0;
  for (int k = 0; k < 4; ++k) {
    part[k] = IntegrateCell(f, v0 + (k / 2) * dv / 2, p0 + (k % 2) * dp / 2, dv / 2, dp / 2);
    sum += part[k];
  }
  if (depth == 0 || std::fabs(sum - whole) <= tol) return sum;
  double refined = 0;
  for (int k = 0; k < 4; ++k)
    refined += IntegrateAdaptive(f, v0 + (k / 2) * dv / 2, p0 + (k % 2) * dp / 2, dv / 2, dp / 2,
                                 part[k], tol, depth - 1);
  return refined;
}

// 16 x 16 starting cells over v in [0, pi/2], phi in [0, pi]; any cell whose quarters differ
// from it by more than tol is split (at most 8 times).
inline double QuadratureAlbedo(const Material& m, vec3 wo, double alpha, double tol) {
  HalfVectorIntegrand f{m, wo, alpha};
  const int n = 16;
  double dv = (M_PI / 2) / n, dp = M_PI / n, sum = 0;
  for (int i = 0; i < n * n; ++i) {
    double v0 = (i / n) * dv, p0 = (i % n) * dp;
    sum += IntegrateAdaptive(f, v0, p0, dv, dp, IntegrateCell(f, v0, p0, dv, dp), tol, 8);
  }
  return 2.0 * sum;  // phi in [pi, 2 pi) mirrors [0, pi)
}

struct Albedo {
  double value, error;  // error: change from a 10x looser tolerance, an estimate of the error
};

inline Albedo QuadratureAlbedo(const Material& m, vec3 wo, double alpha) {
  double fine = QuadratureAlbedo(m, wo, alpha, 1e-8);
  double coarse = QuadratureAlbedo(m, wo, alpha, 1e-7);
  return {fine, std::fabs(fine - coarse)};
}

}  // namespace pt::test
