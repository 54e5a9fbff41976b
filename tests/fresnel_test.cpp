// Fresnel terms and refraction against independent double-precision references.
// All checks here are deterministic (no sampling); tolerances cover float round-off only.
#include <gtest/gtest.h>

#include <cmath>

#include "src/materials/fresnel.h"

namespace pt {
namespace {

// Unpolarised reflectance from the angle forms of the s/p amplitudes (Hecht 4.42-4.43):
// r_s = -sin(ti - tt) / sin(ti + tt), r_p = tan(ti - tt) / tan(ti + tt), computed in double.
// cosI < 0: arriving from inside (relative index 1 / eta).
double FresnelReference(double cosI, double eta) {
  if (cosI < 0) {
    eta = 1 / eta;
    cosI = -cosI;
  }
  double thetaI = std::acos(std::min(1.0, cosI));
  double sinT = std::sin(thetaI) / eta;
  if (sinT >= 1) return 1.0;
  double thetaT = std::asin(sinT);
  if (thetaI < 1e-7) return std::pow((eta - 1) / (eta + 1), 2);  // normal incidence limit
  double rs = -std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT);
  double rp = std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT);
  if (std::fabs(thetaI + thetaT - M_PI / 2) < 1e-12) rp = 0;  // Brewster: tan(pi/2) blows up
  return 0.5 * (rs * rs + rp * rp);
}

const float kEtas[] = {1.2f, 1.33f, 1.5f, 2.4f};

// Float round-off allowance: cos(theta_t) = sqrt(1 - sin^2(theta_t)) amplifies the absolute
// error of sin^2 (a few float epsilons) by 1 / (2 cos(theta_t)), which grows near the critical
// angle; elsewhere a few float epsilons of R. (A sweep of 8e5 angles peaks at 0.43 of this.)
double FresnelTolerance(double cosI, double eta) {
  if (cosI < 0) eta = 1 / eta;
  double sin2T = (1 - cosI * cosI) / (eta * eta);
  double cosT = std::sqrt(std::max(0.0, 1 - sin2T));
  return 2e-6 + 1e-6 / std::max(cosT, 1e-3);
}

TEST(FresnelTest, MatchesPolarisedFormulaBothSides) {
  for (float eta : kEtas) {
    double thetaCritical = std::asin(1.0 / eta);
    for (int i = 0; i <= 400; ++i) {
      double theta = (M_PI / 2) * i / 400.0;
      float c = float(std::cos(theta));
      // Outside: every angle.
      EXPECT_NEAR(FresnelDielectric(c, eta), FresnelReference(c, eta), FresnelTolerance(c, eta))
          << "eta " << eta << " theta " << theta;
      // Inside: except within 1e-4 rad of the critical angle (the TIR test covers it).
      if (std::fabs(theta - thetaCritical) < 1e-4) continue;
      EXPECT_NEAR(FresnelDielectric(-c, eta), FresnelReference(-double(c), eta),
                  FresnelTolerance(-double(c), eta))
          << "inside, eta " << eta << " theta " << theta;
    }
  }
}

TEST(FresnelTest, NormalIncidence) {
  for (float eta : kEtas) {
    double expect = std::pow((eta - 1.0) / (eta + 1.0), 2);
    EXPECT_NEAR(FresnelDielectric(1.0f, eta), expect, 1e-7);
    EXPECT_NEAR(FresnelDielectric(-1.0f, eta), expect, 1e-7);  // same from inside
  }
  for (float c : {1.0f, 0.5f, 0.01f}) EXPECT_NEAR(FresnelDielectric(c, 1.0f), 0.0f, 1e-7f);
}

TEST(FresnelTest, GrazingTendsToOne) {
  for (float eta : kEtas) {
    EXPECT_EQ(FresnelDielectric(0.0f, eta), 1.0f);
    EXPECT_GT(FresnelDielectric(1e-4f, eta), 0.999f);
    float previous = 0.0f;  // reflectance grows towards grazing beyond Brewster's angle
    for (float c = 0.3f; c >= 0.0f; c -= 0.01f) {
      float r = FresnelDielectric(c, eta);
      EXPECT_GE(r, previous);
      previous = r;
    }
  }
}

TEST(FresnelTest, TotalInternalReflectionPastCriticalAngle) {
  for (float eta : kEtas) {
    double thetaCritical = std::asin(1.0 / eta);
    for (double delta : {1e-3, 1e-2, 0.2}) {
      double past = thetaCritical + delta;
      if (past < M_PI / 2) {
        EXPECT_EQ(FresnelDielectric(-float(std::cos(past)), eta), 1.0f);
      }
      double below = thetaCritical - delta;  // just below: not total
      float r = FresnelDielectric(-float(std::cos(below)), eta);
      EXPECT_LT(r, 1.0f) << "eta " << eta << " delta " << delta;
      double cosBelow = double(float(std::cos(below)));
      EXPECT_NEAR(r, FresnelReference(-cosBelow, eta), FresnelTolerance(-cosBelow, eta));
    }
    vec3 wt;
    float etap;
    double past = thetaCritical + 1e-3;
    vec3 wi(float(std::sin(past)), 0.0f, -float(std::cos(past)));
    EXPECT_FALSE(Refract(wi, vec3(0, 0, 1), eta, &etap, &wt));
  }
}

TEST(FresnelTest, ReciprocalAcrossTheInterface) {
  // The reflectance seen from outside at theta_i equals that from inside at theta_t.
  for (float eta : kEtas) {
    for (float c = 0.05f; c <= 1.0f; c += 0.05f) {
      vec3 wi(SafeSqrt(1 - c * c), 0.0f, c), wt;
      float etap;
      ASSERT_TRUE(Refract(wi, vec3(0, 0, 1), eta, &etap, &wt));
      EXPECT_NEAR(FresnelDielectric(c, eta), FresnelDielectric(wt.z, eta), 1e-5f);
    }
  }
}

TEST(FresnelTest, RefractFollowsSnell) {
  for (float eta : kEtas) {
    for (float c = -1.0f; c <= 1.0f; c += 0.0625f) {
      if (c == 0.0f) continue;
      vec3 wi = glm::normalize(vec3(0.6f * SafeSqrt(1 - c * c), 0.8f * SafeSqrt(1 - c * c), c));
      vec3 wt;
      float etap = 0.0f;
      if (!Refract(wi, vec3(0, 0, 1), eta, &etap, &wt)) {
        EXPECT_LT(c, 0.0f);  // only from inside
        continue;
      }
      EXPECT_FLOAT_EQ(etap, c > 0 ? eta : 1.0f / eta);
      EXPECT_NEAR(glm::length(wt), 1.0f, 1e-5f);
      EXPECT_LT(wt.z * c, 0.0f);  // crosses to the other side
      float sinI = glm::length(vec2(wi.x, wi.y)), sinT = glm::length(vec2(wt.x, wt.y));
      EXPECT_NEAR(sinI, etap * sinT, 1e-5f);
      EXPECT_NEAR(wt.x * wi.y - wt.y * wi.x, 0.0f, 1e-6f);  // plane of incidence
    }
  }
}

TEST(FresnelTest, SchlickEndpointsAndSymmetry) {
  vec3 f0(0.04f, 0.5f, 0.95f);
  vec3 normal = FresnelSchlick(f0, 1.0f), grazing = FresnelSchlick(f0, 0.0f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(normal[c], f0[c]);
    EXPECT_FLOAT_EQ(grazing[c], 1.0f);
    float cosTheta = 0.3f;
    float expect = f0[c] + (1 - f0[c]) * std::pow(1 - cosTheta, 5.0f);
    EXPECT_NEAR(FresnelSchlick(f0, cosTheta)[c], expect, 1e-6f);
    EXPECT_EQ(FresnelSchlick(f0, -cosTheta)[c], FresnelSchlick(f0, cosTheta)[c]);
  }
}

}  // namespace
}  // namespace pt
