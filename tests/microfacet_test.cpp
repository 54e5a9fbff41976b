// The GGX distribution (src/materials/microfacet.h): D and Lambda against their textbook forms,
// D normalised over projected area, the visible-normal density normalised (Monte Carlo), and
// Heitz's visible-normal sampling against that density (chi-square). Then the lobes built on
// it: rough conductor (both sides), rough dielectric (outside and inside) and plastic (smooth
// and rough, both sides) sample exactly PdfBsdf (chi-square), and each sample's path weight
// is EvalBsdf |cos| / PdfBsdf of its direction.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <sstream>

#include "src/materials/bsdf.h"
#include "src/materials/microfacet.h"
#include "tests/bsdf_check_util.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::ChiSquareAccurate;
using test::ChiSquareGrid;
using test::CheckLobe;
using test::GridFor;
using test::kZ1e4;
using test::RelativeDifference;

using test::kChiSquareAlpha;  // per-assertion false-alarm probability

using test::Uniform;

vec3 Spherical(double theta, double phi) { return test::SphericalToDirection(theta, phi); }

// Viewing directions on both sides, normal to near-grazing.
std::vector<vec3> Views() {
  return {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
          glm::normalize(vec3(0.5f, 0.7f, 0.2f)), glm::normalize(vec3(-0.99f, 0.0f, 0.08f)),
          glm::normalize(vec3(0.3f, -0.4f, -0.866f))};
}

TEST(MicrofacetTest, DAndLambdaMatchTextbookForms) {
  // D = 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2), Lambda = (sqrt(1 + a^2 tan^2) - 1) / 2, in
  // double; float round-off only (the stable forms avoid cancellation, the reference does not
  // need to at these angles).
  for (double alpha : {0.01, 0.09, 0.36, 1.0}) {
    GgxDistribution d{float(alpha)};
    for (double theta : {0.0, 0.05, 0.3, 0.8, 1.3, 1.55}) {
      vec3 w = Spherical(theta, 0.7);
      double t2 = std::pow(std::tan(theta), 2), c4 = std::pow(std::cos(theta), 4);
      double dRef = 1.0 / (M_PI * alpha * alpha * c4 * std::pow(1.0 + t2 / (alpha * alpha), 2));
      double lRef = (std::sqrt(1.0 + alpha * alpha * t2) - 1.0) / 2.0;
      EXPECT_NEAR(d.D(w), dRef, 2e-5 * dRef) << alpha << " " << theta;
      EXPECT_NEAR(d.Lambda(w), lRef, 2e-5 * lRef + 1e-7) << alpha << " " << theta;
      EXPECT_EQ(d.D(w), d.D(-w));  // even: callers may pass either orientation
    }
    EXPECT_EQ(d.G1(vec3(1, 0, 0)), 0.0f);  // grazing: fully masked
  }
}

// Integral of D(wm) cos(wm) over the hemisphere is 1 (microfacet area projects onto the unit
// macro area). Deterministic: composite Simpson in v with tan(theta) = alpha tan(v), which
// spreads the peak evenly; 20000 intervals of a smooth integrand, error far below 1e-6.
TEST(MicrofacetTest, DistributionProjectsToUnitArea) {
  for (double alpha : {0.001, 0.01, 0.09, 0.36, 1.0}) {
    GgxDistribution d{float(alpha)};
    const int n = 20000;
    double h = (M_PI / 2) / n, sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      double v = std::min(i * h, M_PI / 2 - 1e-12);
      double theta = std::atan(alpha * std::tan(v));
      double dTheta = alpha / (std::pow(std::cos(v), 2) + std::pow(alpha * std::sin(v), 2));
      double f = d.D(Spherical(theta, 0.0)) * std::cos(theta) * std::sin(theta) * dTheta;
      sum += f * ((i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    EXPECT_NEAR(2.0 * M_PI * sum * h / 3.0, 1.0, 1e-5) << "alpha " << alpha;
  }
}

// Integral of VisibleD(w, wm) over wm.z > 0 is 1 for every w. Monte Carlo with the defensive
// mixture q = (uniform hemisphere + D cos) / 2, so the estimator VisibleD / q is bounded (by
// 4 alpha^2 G1 / |cos w| near the horizon, by 2 G1 |w.wm| / (|cos w| cos wm) at the peak) and
// the CLT tolerance below is valid.
TEST(MicrofacetTest, VisibleNormalPdfIntegratesToOne) {
  uint32_t seed = 200;
  for (float alpha : {0.01f, 0.09f, 0.36f, 1.0f}) {
    GgxDistribution d{alpha};
    for (vec3 w : Views()) {
      Uniform u(seed++);
      test::MeanAccumulator acc;
      for (int i = 0; i < 100000; ++i) {
        vec3 wm;
        vec2 uv = u.Get2();
        if (u() < 0.5f) {
          wm = SampleUniformSphere(uv);
          wm.z = fabsf(wm.z);
        } else {  // D cos sampling: tan^2 theta = alpha^2 x / (1 - x)
          float t2 = alpha * alpha * uv.x / (1.0f - uv.x);
          float c = 1.0f / sqrtf(1.0f + t2), s = SafeSqrt(1.0f - c * c);
          wm = vec3(s * cosf(2 * kPi * uv.y), s * sinf(2 * kPi * uv.y), c);
        }
        double q = 0.5 / (2.0 * M_PI) + 0.5 * double(d.D(wm)) * wm.z;
        acc.Add(double(d.VisibleD(w, wm)) / q);
      }
      test::MeanEstimate e = acc.Result();
      // Mean of i.i.d. bounded terms: by the CLT, |mean - 1| > z sigma / sqrt(n) with
      // z = 3.89 has two-sided false-alarm probability 1e-4.
      EXPECT_NEAR(e.mean, 1.0, kZ1e4 * e.stdError) << "alpha " << alpha << " w.z " << w.z;
    }
  }
}

// Heitz's sampler draws exactly VisibleD(w, .) (chi-square), from either side.
TEST(MicrofacetTest, VisibleNormalSamplingMatchesPdf) {
  uint32_t seed = 300;
  ChiSquareGrid grid;
  for (float alpha : {0.09f, 0.36f, 1.0f}) {
    GgxDistribution d{alpha};
    for (vec3 w : Views()) {
      Uniform u(seed++);
      auto sample = [&](vec3* wm) { *wm = d.SampleVisibleNormal(w, u.Get2()); return true; };
      auto pdf = [&](vec3 wm) { return wm.z > 0 ? double(d.VisibleD(w, wm)) : 0.0; };
      test::ChiSquareResult r = ChiSquareAccurate(sample, pdf, 100000, grid);
      // Chi-square goodness of fit: false-alarm probability kChiSquareAlpha = 1e-4 per case.
      EXPECT_GT(r.pValue, kChiSquareAlpha) << "alpha " << alpha << " w.z " << w.z << ": "
                                           << r.message;
    }
  }
}

// ---- The GGX lobes of bsdf.h ----

Material RoughConductor(vec3 f0, float roughness) {
  Material m;
  m.type = MaterialType::kConductor;
  m.albedo = f0;
  m.roughness = roughness;
  return m;
}

Material RoughGlass(float ior, float roughness) {
  Material m;
  m.type = MaterialType::kDielectric;
  m.ior = ior;
  m.roughness = roughness;
  return m;
}

TEST(RoughConductorTest, SamplingMatchesPdfOnBothSides) {
  uint32_t seed = 400;
  for (float roughness : {0.1f, 0.3f, 0.6f, 1.0f}) {
    Material m = RoughConductor(vec3(0.95f, 0.64f, 0.54f), roughness);
    ASSERT_TRUE(HasNonDeltaLobe(m));
    for (vec3 wo : Views()) CheckLobe(m, wo, seed++, 100000);
  }
}

// Power of the test above: a lobe sampled at 10% more alpha than its pdf claims is rejected.
// Fixed seed, so deterministic.
TEST(RoughConductorTest, ChiSquareRejectsAWrongAlpha) {
  Material sampled = RoughConductor(vec3(0.9f), 0.3f);
  Material claimed = RoughConductor(vec3(0.9f), 0.3f * std::sqrt(1.1f));
  vec3 wo = glm::normalize(vec3(0.6f, 0.0f, 0.8f));
  Uniform u(99);
  auto sample = [&](vec3* w) {
    BsdfSample s;
    if (!SampleBsdf(sampled, wo, u(), u.Get2(), &s)) return false;
    *w = s.wi;
    return true;
  };
  auto pdf = [&](vec3 w) { return double(PdfBsdf(claimed, wo, w)); };
  test::ChiSquareResult r = ChiSquareAccurate(sample, pdf, 100000, GridFor(claimed, wo));
  EXPECT_LT(r.pValue, 1e-12) << r.message;
}

TEST(RoughConductorTest, IsReciprocalAndMirroredBelow) {
  Material m = RoughConductor(vec3(0.9f, 0.6f, 0.3f), 0.5f);
  Uniform u(7);
  for (int i = 0; i < 2000; ++i) {
    vec3 a = SampleUniformSphere(u.Get2()), b = SampleUniformSphere(u.Get2());
    vec3 fab = EvalBsdf(m, a, b), fba = EvalBsdf(m, b, a);
    EXPECT_LE(RelativeDifference(fab, fba), 1e-5f);  // Schlick at wo.wm = wi.wm: symmetric
    vec3 flipped = EvalBsdf(m, FlipZ(a), FlipZ(b));
    EXPECT_EQ(fab, flipped);  // two-sided: the back face is the front mirrored
    if (!SameHemisphere(a, b)) {
      EXPECT_TRUE(IsBlack(fab));
    }
  }
}

TEST(RoughDielectricTest, SamplingMatchesPdfOutsideAndInside) {
  uint32_t seed = 500;
  // Inside views include one past the critical angle of both indices (total internal
  // reflection of most microfacets).
  std::vector<vec3> views = {vec3(0, 0, 1), glm::normalize(vec3(0.9f, 0.3f, 0.15f)),
                             glm::normalize(vec3(0.2f, 0.1f, -1.0f)),
                             glm::normalize(vec3(0.5f, -0.3f, -0.6f)),
                             glm::normalize(vec3(0.85f, 0.3f, -0.3f))};
  struct Case {
    float ior, roughness;
  };
  for (Case c : {Case{1.33f, 0.3f}, Case{1.33f, 0.6f}, Case{1.5f, 0.1f}, Case{1.5f, 0.3f},
                 Case{1.5f, 1.0f}, Case{2.4f, 0.3f}}) {
    Material m = RoughGlass(c.ior, c.roughness);
    ASSERT_TRUE(HasNonDeltaLobe(m));
    for (vec3 wo : views) CheckLobe(m, wo, seed++, 100000);
  }
}

// Refraction follows Snell's law about the microfacet it was sampled on, so its radiance is
// scaled by 1 / etap^2 and etap is the index ratio actually crossed.
TEST(RoughDielectricTest, TransmissionReportsTheIndexCrossed) {
  Material m = RoughGlass(1.5f, 0.5f);
  Uniform u(9);
  int refractions = 0;
  for (int i = 0; i < 4000; ++i) {
    vec3 wo = SampleUniformSphere(u.Get2());
    BsdfSample s;
    if (wo.z == 0.0f || !SampleBsdf(m, wo, 0.9999f, u.Get2(), &s) || !s.isTransmission) continue;
    ++refractions;
    EXPECT_FLOAT_EQ(s.eta, wo.z > 0.0f ? 1.5f : 1.0f / 1.5f);
    EXPECT_LT(s.wi.z * wo.z, 0.0f);
  }
  EXPECT_GT(refractions, 1000);
}

// ---- Plastic (plastic.h): smooth coat (a delta lobe, which the chi-square sees as the mass
// PdfBsdf leaves out) and GGX coat, over the diffuse base; two-sided ----

TEST(PlasticTest, SamplingMatchesPdfOnBothSides) {
  uint32_t seed = 600;
  for (float roughness : {0.0f, 0.3f, 0.6f}) {
    Material m;
    m.type = MaterialType::kPlastic;
    m.albedo = vec3(0.8f, 0.3f, 0.1f);
    m.ior = 1.5f;
    m.roughness = roughness;
    ASSERT_TRUE(HasNonDeltaLobe(m));
    for (vec3 wo : Views()) CheckLobe(m, wo, seed++, 100000);
  }
}

}  // namespace
}  // namespace pt
