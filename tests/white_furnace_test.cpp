// White furnace: how much of the light arriving along wo each lobe sends back, E(wo) =
// integral of f(wo, wi) |cos wi| dwi. Computed twice: by deterministic quadrature of
// EvalBsdf |cos| (no sampling code involved) and by the mean of SampleBsdf's path weights.
//  - A conductor of albedo 1 (Schlick F = 1) keeps exactly the single-scattering GGX albedo:
//    E <= 1 everywhere, each weight is G / G1 <= 1, and the Monte Carlo mean matches the
//    quadrature. The quadrature's figures (alpha = roughness^2):
//      roughness         0.1      0.3      0.6      1.0
//      E(mu = 1)       0.99990  0.99067  0.82453  0.30685
//      E(mu = 0.5)     0.99974  0.97509  0.78212  0.45069
//      E(mu = 0.2)     0.99859  0.91403  0.82576  0.64165
//    Rough GGX loses most near normal incidence, where reflections about steep microfacets
//    leave below the horizon: at alpha = 1 the visible normals are cosine-distributed, the
//    reflection leaves at twice their angle and G / G1 = 2 cos(2t) / (1 + cos(2t)), so
//    E(1) = integral of x / (1 + x) over [0, 1] = 1 - ln 2, which the test checks.
//  - Rough glass: reflection plus transmission weights, with the 1 / eta^2 radiance scaling
//    undone, never exceed 1 (each is G / G1 <= 1), in expectation nor per sample.
//  - Plastic of albedo 1: smooth, E = F + (1 - F) exactly; rough, at most ~1e-3 above 1 (the
//    documented approximation of plastic.h), and the Monte Carlo mean matches the quadrature.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <sstream>

#include "src/materials/bsdf.h"
#include "tests/albedo_quadrature.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

using test::Albedo;
using test::QuadratureAlbedo;
using test::Uniform;

Material Make(MaterialType type, vec3 albedo, float ior, float roughness) {
  Material m;
  m.type = type;
  m.albedo = albedo;
  m.ior = ior;
  m.roughness = roughness;
  return m;
}

vec3 View(float mu) { return vec3(SafeSqrt(1.0f - mu * mu), 0.0f, mu); }

// Mean path weight of SampleBsdf (0 where it fails: the energy lost), red channel; the
// largest single weight (transmitted ones times etap^2) goes to *maxWeight.
test::MeanEstimate SampledAlbedo(const Material& m, vec3 wo, uint32_t seed, int n,
                                 float* maxWeight) {
  Uniform u(seed);
  test::MeanAccumulator acc;
  *maxWeight = 0.0f;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    float w = 0.0f;
    if (SampleBsdf(m, wo, u(), u.Get2(), &s)) {
      w = s.f.x * AbsCosTheta(s.wi) / s.pdf;
      if (s.isTransmission) w *= s.eta * s.eta;  // undo the radiance scaling
    }
    *maxWeight = std::max(*maxWeight, w);
    acc.Add(w);
  }
  return acc.Result();
}

TEST(WhiteFurnaceTest, ConductorLosesOnlyWhatSingleScatteringGgxLoses) {
  uint32_t seed = 10;
  for (float roughness : {0.1f, 0.3f, 0.6f, 1.0f}) {
    Material m = Make(MaterialType::kConductor, vec3(1.0f), 1.5f, roughness);
    for (float mu : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f}) {
      Albedo q = QuadratureAlbedo(m, View(mu), GgxAlpha(roughness));
      EXPECT_LT(q.error, 1e-4) << "roughness " << roughness << " mu " << mu;
      EXPECT_LE(q.value, 1.0 + q.error) << "roughness " << roughness << " mu " << mu;
      if (roughness == 1.0f && mu == 1.0f) {
        EXPECT_NEAR(q.value, 1.0 - std::log(2.0), 1e-6);  // the closed form above
      }
      float maxWeight;
      for (float side : {1.0f, -1.0f}) {  // two-sided: the back face is the front mirrored
        vec3 wo = View(mu) * vec3(1.0f, 1.0f, side);
        test::MeanEstimate e = SampledAlbedo(m, wo, seed++, 40000, &maxWeight);
        // Mean of i.i.d. weights in [0, 1]: by the CLT, |mean - E| > z sigma / sqrt(n) with
        // z = 3.89 has two-sided false-alarm probability 1e-4; the quadrature error adds.
        EXPECT_NEAR(e.mean, q.value, kZ1e4 * e.stdError + q.error)
            << "roughness " << roughness << " mu " << mu << " side " << side;
        EXPECT_LE(maxWeight, 1.0f + 1e-5f);  // G / G1 <= 1: no sample creates energy
      }
    }
  }
}

TEST(WhiteFurnaceTest, ConductorAlbedoNeverExceedsOne) {
  // More roughnesses and angles, by the quadrature alone (deterministic).
  for (float roughness : {0.05f, 0.2f, 0.45f, 0.8f}) {
    Material m = Make(MaterialType::kConductor, vec3(1.0f), 1.5f, roughness);
    for (float mu : {0.9f, 0.6f, 0.3f, 0.1f}) {
      Albedo q = QuadratureAlbedo(m, View(mu), GgxAlpha(roughness));
      EXPECT_LE(q.value, 1.0 + q.error) << "roughness " << roughness << " mu " << mu;
      EXPECT_GT(q.value, 0.0) << "roughness " << roughness << " mu " << mu;
    }
  }
}

TEST(WhiteFurnaceTest, RoughGlassNeverCreatesEnergy) {
  uint32_t seed = 100;
  for (float ior : {1.33f, 1.5f}) {
    for (float roughness : {0.3f, 0.6f, 1.0f}) {
      Material m = Make(MaterialType::kDielectric, vec3(0.0f), ior, roughness);
      for (float mu : {1.0f, 0.5f, 0.1f, -1.0f, -0.8f, -0.4f}) {  // outside, then inside
        float maxWeight;
        test::MeanEstimate e = SampledAlbedo(m, View(fabsf(mu)) * vec3(1, 1, mu < 0 ? -1 : 1),
                                             seed++, 40000, &maxWeight);
        // One-sided CLT bound: P(mean > E + z sigma / sqrt(n)) < 1e-4 for any E <= 1.
        EXPECT_LE(e.mean, 1.0 + kZ1e4 * e.stdError) << "ior " << ior << " mu " << mu;
        EXPECT_LE(maxWeight, 1.0f + 1e-5f) << "ior " << ior << " mu " << mu;
      }
    }
  }
}

TEST(WhiteFurnaceTest, PlasticReflectsAtMostWhatItReceives) {
  struct Case {
    float roughness, ior, mu;
  };
  // Smooth at three indices; rough where the overshoot peaks (ior 1.33, roughness 0.3, mu
  // 0.65: +7.1e-4) and where the coat is roughest.
  const Case cases[] = {{0.0f, 1.33f, 1.0f}, {0.0f, 1.5f, 0.7f}, {0.0f, 2.0f, 0.3f},
                        {0.0f, 1.5f, 0.1f},  {0.3f, 1.33f, 0.65f}, {0.3f, 1.33f, 0.2f},
                        {0.3f, 1.5f, 1.0f},  {1.0f, 1.5f, 1.0f},  {1.0f, 1.5f, 0.3f}};
  uint32_t seed = 200;
  for (const Case& c : cases) {
    Material m = Make(MaterialType::kPlastic, vec3(1.0f), c.ior, c.roughness);
    bool smooth = IsSmooth(m);
    // Smooth: the delta coat reflects F(mu) exactly; the quadrature sees the base alone.
    double coat = smooth ? FresnelDielectric(c.mu, c.ior) : 0.0;
    Albedo q = QuadratureAlbedo(m, View(c.mu), smooth ? 1.0 : GgxAlpha(c.roughness));
    double total = coat + q.value;
    std::ostringstream what;
    what << "roughness " << c.roughness << " ior " << c.ior << " mu " << c.mu;
    EXPECT_LT(q.error, 1e-4) << what.str();
    if (smooth) {
      // F + (1 - F) = 1 exactly: fdr_int comes from fdr_ext by reciprocity.
      EXPECT_NEAR(total, 1.0, 2e-5 + q.error) << what.str();
    } else {
      // The smooth-coat transmittance under a rough coat overshoots by at most ~7.1e-4.
      EXPECT_LE(total, 1.0 + 1e-3 + q.error) << what.str();
    }
    float maxWeight;
    test::MeanEstimate e = SampledAlbedo(m, View(c.mu), seed++, 40000, &maxWeight);
    // Two-sided CLT test of the sampled weights against the quadrature: 1e-4.
    EXPECT_NEAR(e.mean, total, kZ1e4 * e.stdError + q.error) << what.str();
  }
}

}  // namespace
}  // namespace pt
