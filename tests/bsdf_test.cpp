// BSDF sampling against its own pdf (chi-square), pdf normalisation, delta lobes (mirror,
// Schlick weight, smooth glass reflect/refract frequencies, total internal reflection), and
// the statistics helpers themselves, which lobes are delta, and plastic (smooth and rough).
// The GGX conductor and dielectric lobes are tested in microfacet_test.cpp, energy in
// white_furnace_test.cpp.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <random>

#include "src/materials/bsdf.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

using test::kChiSquareAlpha;  // per-assertion false-alarm probability

using test::Uniform;

Material Diffuse(vec3 albedo) {
  Material m;
  m.type = MaterialType::kDiffuse;
  m.albedo = albedo;
  return m;
}
Material Conductor(vec3 f0) {
  Material m;
  m.type = MaterialType::kConductor;
  m.albedo = f0;
  return m;
}
Material Glass(float ior) {
  Material m;
  m.type = MaterialType::kDielectric;
  m.ior = ior;
  return m;
}

// Outgoing directions on both sides, including near-grazing ones.
std::vector<vec3> TestDirections() {
  return {glm::normalize(vec3(0, 0, 1)),        glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
          glm::normalize(vec3(0.9f, 0.3f, 0.1f)), glm::normalize(vec3(0.3f, 0.4f, -0.866f)),
          glm::normalize(vec3(-0.2f, 0.1f, -1.0f)), glm::normalize(vec3(0.7f, -0.7f, -0.05f))};
}

// ---- The statistics helpers ----

TEST(BsdfStatUtilTest, ChiSquarePValueMatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0, 200.0}) {
    // dof 2: exp(-x/2); dof 1: erfc(sqrt(x/2)); dof 4: exp(-x/2)(1 + x/2).
    EXPECT_NEAR(test::ChiSquarePValue(x, 2), std::exp(-x / 2), 1e-12 + 1e-10 * std::exp(-x / 2));
    double p1 = std::erfc(std::sqrt(x / 2));
    EXPECT_NEAR(test::ChiSquarePValue(x, 1), p1, 1e-12 + 1e-9 * p1);
    double p4 = std::exp(-x / 2) * (1 + x / 2);
    EXPECT_NEAR(test::ChiSquarePValue(x, 4), p4, 1e-12 + 1e-9 * p4);
  }
  // Large dof: the median of chi^2_k is close to k (1 - 2/(9k))^3.
  double k = 500, median = k * std::pow(1 - 2 / (9 * k), 3);
  EXPECT_NEAR(test::ChiSquarePValue(median, 500), 0.5, 1e-3);
}

TEST(BsdfStatUtilTest, BinomialPValueMatchesExactSmallCase) {
  // n = 10, p = 1/2, k = 2: P(X <= 2) = 56 / 1024, two-sided 112 / 1024.
  EXPECT_NEAR(test::BinomialTwoSidedPValue(10, 2, 0.5), 112.0 / 1024.0, 1e-12);
  EXPECT_NEAR(test::BinomialTwoSidedPValue(10, 5, 0.5), 1.0, 1e-12);
  EXPECT_EQ(test::BinomialTwoSidedPValue(10, 0, 0.0), 1.0);
  EXPECT_EQ(test::BinomialTwoSidedPValue(10, 1, 0.0), 0.0);
}

TEST(BsdfStatUtilTest, ChiSquareRejectsAWrongPdf) {
  // Power check: cosine-weighted samples tested against the uniform-hemisphere pdf must be
  // rejected. Fixed seed, so deterministic; with 1e5 samples the statistic is ~1e4 standard
  // deviations off, so any seed gives p < 1e-12.
  Uniform u(7);
  auto sample = [&](vec3* w) { *w = SampleCosineHemisphere(u.Get2()); return true; };
  auto pdf = [](vec3 w) { return w.z > 0 ? 1.0 / (2.0 * M_PI) : 0.0; };
  test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 100000);
  EXPECT_LT(r.pValue, 1e-12) << r.message;
}

// ---- Non-delta lobes: sampling follows the pdf ----

TEST(BsdfTest, CosineHemisphereSamplingMatchesPdf) {
  Uniform u(1);
  auto sample = [&](vec3* w) { *w = SampleCosineHemisphere(u.Get2()); return true; };
  auto pdf = [](vec3 w) { return double(CosineHemispherePdf(w.z)); };
  test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 400000);
  // Chi-square goodness of fit: false-alarm probability kChiSquareAlpha = 1e-4.
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;
}

TEST(BsdfTest, DiffuseSamplingMatchesPdf) {
  Material m = Diffuse(vec3(0.8f, 0.5f, 0.2f));
  uint32_t seed = 10;
  for (vec3 wo : TestDirections()) {
    Uniform u(seed++);
    int mismatches = 0;
    auto sample = [&](vec3* w) {
      BsdfSample s;
      if (!SampleBsdf(m, wo, u(), u.Get2(), &s)) return false;
      // The sample must report exactly what Eval/Pdf say about its direction.
      if (s.pdf != PdfBsdf(m, wo, s.wi) || s.f != EvalBsdf(m, wo, s.wi) || s.isDelta) ++mismatches;
      *w = s.wi;
      return true;
    };
    auto pdf = [&](vec3 w) { return double(PdfBsdf(m, wo, w)); };
    test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 200000);
    // Chi-square goodness of fit: false-alarm probability kChiSquareAlpha = 1e-4 per direction.
    EXPECT_GT(r.pValue, kChiSquareAlpha) << "wo = " << wo.x << " " << wo.y << " " << wo.z << ": "
                                         << r.message;
    EXPECT_EQ(mismatches, 0);
  }
}

TEST(BsdfTest, DiffusePdfIntegratesToOne) {
  Material m = Diffuse(vec3(0.5f));
  uint32_t seed = 100;
  for (vec3 wo : TestDirections()) {
    Uniform u(seed++);
    test::MeanAccumulator acc;
    for (int i = 0; i < 200000; ++i) {
      vec3 w = SampleUniformSphere(u.Get2());
      acc.Add(double(PdfBsdf(m, wo, w)) / double(UniformSpherePdf()));
    }
    test::MeanEstimate e = acc.Result();
    // Mean of n i.i.d. terms (bounded in [0, 4], sigma ~ 1.29): by the CLT the two-sided
    // false-alarm probability of |mean - 1| > z sigma / sqrt(n) with z = 3.89 is 1e-4.
    EXPECT_NEAR(e.mean, 1.0, kZ1e4 * e.stdError) << "wo.z = " << wo.z;
  }
}

TEST(BsdfTest, DiffuseWeightIsAlbedo) {
  // f |cos| / pdf is exactly the albedo for cosine sampling: deterministic, float round-off.
  vec3 albedo(0.8f, 0.5f, 0.2f);
  Material m = Diffuse(albedo);
  Uniform u(3);
  for (vec3 wo : TestDirections()) {
    for (int i = 0; i < 1000; ++i) {
      BsdfSample s;
      // False only for an exactly grazing direction (pdf 0), a ~2^-23 event: skip it.
      if (!SampleBsdf(m, wo, u(), u.Get2(), &s)) continue;
      EXPECT_TRUE(SameHemisphere(wo, s.wi));
      vec3 w = s.f * AbsCosTheta(s.wi) / s.pdf;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(w[c], albedo[c], 1e-5f);
      EXPECT_FALSE(s.isTransmission);
      EXPECT_EQ(s.eta, 1.0f);
    }
  }
  BsdfSample black;
  EXPECT_FALSE(SampleBsdf(Diffuse(vec3(0.0f)), vec3(0, 0, 1), 0.5f, vec2(0.5f), &black));
}

// ---- Delta lobes ----

TEST(BsdfTest, MirrorReflectsExactlyWithSchlickWeight) {
  vec3 f0(0.95f, 0.64f, 0.54f);
  Material m = Conductor(f0);
  Uniform u(4);
  for (int i = 0; i < 2000; ++i) {
    vec3 wo = SampleUniformSphere(u.Get2());  // both sides: the conductor is two-sided
    if (wo.z == 0.0f) continue;
    BsdfSample s;
    ASSERT_TRUE(SampleBsdf(m, wo, u(), u.Get2(), &s));
    vec3 expectWi = Reflect(wo, vec3(0, 0, 1));
    EXPECT_NEAR(glm::length(s.wi - expectWi), 0.0f, 1e-6f);
    EXPECT_EQ(s.wi.z, wo.z);
    EXPECT_TRUE(s.isDelta);
    EXPECT_FALSE(s.isTransmission);
    EXPECT_EQ(s.pdf, 1.0f);
    vec3 weight = s.f * AbsCosTheta(s.wi) / s.pdf;
    vec3 schlick = FresnelSchlick(f0, wo.z);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(weight[c], schlick[c], 2e-6f * schlick[c] + 1e-7f);
    // A delta lobe has no density and no value for any given pair of directions.
    EXPECT_EQ(PdfBsdf(m, wo, s.wi), 0.0f);
    EXPECT_TRUE(IsBlack(EvalBsdf(m, wo, s.wi)));
  }
  EXPECT_FALSE(HasNonDeltaLobe(m));
}

// Reflection vs refraction counts of smooth glass follow FresnelDielectric (binomial test).
void CheckGlassFrequencies(float ior, float cosThetaO, uint32_t seed) {
  Material m = Glass(ior);
  float sinThetaO = SafeSqrt(1.0f - cosThetaO * cosThetaO);
  vec3 wo(sinThetaO, 0.0f, cosThetaO);
  float expectR = FresnelDielectric(cosThetaO, ior);
  Uniform u(seed);
  const int64_t n = 100000;
  int64_t reflections = 0;
  for (int64_t i = 0; i < n; ++i) {
    BsdfSample s;
    ASSERT_TRUE(SampleBsdf(m, wo, u(), u.Get2(), &s));
    ASSERT_TRUE(s.isDelta);
    if (s.isTransmission) {
      ASSERT_LT(s.wi.z * wo.z, 0.0f);
      ASSERT_NEAR(s.pdf, 1.0f - expectR, 1e-6f);
    } else {
      ASSERT_EQ(s.wi, vec3(-wo.x, -wo.y, wo.z));
      ASSERT_NEAR(s.pdf, expectR, 1e-6f);
      ++reflections;
    }
  }
  double p = test::BinomialTwoSidedPValue(n, reflections, expectR);
  // Exact two-sided binomial test: false-alarm probability <= kChiSquareAlpha = 1e-4.
  EXPECT_GT(p, kChiSquareAlpha) << "ior " << ior << " cos " << cosThetaO << ": " << reflections
                                << " of " << n << ", expected R = " << expectR;
}

TEST(BsdfTest, GlassReflectRefractFrequenciesFollowFresnel) {
  uint32_t seed = 20;
  for (float ior : {1.5f, 2.4f}) {
    for (float c : {1.0f, 0.7f, 0.3f, 0.08f}) CheckGlassFrequencies(ior, c, seed++);  // outside
    // Inside: below the critical angle asin(1/ior) (cos above sqrt(1 - 1/ior^2)).
    float cosCritical = std::sqrt(1.0f - 1.0f / (ior * ior));
    for (float c : {1.0f, 0.95f, cosCritical + 0.02f}) CheckGlassFrequencies(ior, -c, seed++);
  }
}

TEST(BsdfTest, GlassTotalInternalReflectionAlwaysReflects) {
  Material m = Glass(1.5f);
  float cosCritical = std::sqrt(1.0f - 1.0f / (1.5f * 1.5f));
  Uniform u(5);
  for (float c : {cosCritical - 0.01f, 0.5f, 0.1f, 0.001f}) {
    vec3 wo(SafeSqrt(1.0f - c * c), 0.0f, -c);  // inside, past the critical angle
    for (int i = 0; i < 1000; ++i) {
      BsdfSample s;
      ASSERT_TRUE(SampleBsdf(m, wo, u(), u.Get2(), &s));
      EXPECT_FALSE(s.isTransmission);
      EXPECT_EQ(s.pdf, 1.0f);
      EXPECT_NEAR(s.f.x * AbsCosTheta(s.wi) / s.pdf, 1.0f, 1e-6f);
    }
  }
}

TEST(BsdfTest, GlassRefractionObeysSnellAndScalesRadiance) {
  const float ior = 1.5f;
  Material m = Glass(ior);
  Uniform u(6);
  for (int i = 0; i < 2000; ++i) {
    vec3 wo = SampleUniformSphere(u.Get2());
    if (wo.z == 0.0f) continue;
    BsdfSample s;
    // uc just below 1 picks refraction whenever it is possible.
    if (!SampleBsdf(m, wo, 0.9999999f, u.Get2(), &s) || !s.isTransmission) continue;
    bool entering = wo.z > 0.0f;
    float etaI = entering ? 1.0f : ior, etaT = entering ? ior : 1.0f;
    // Sines from the tangential components: sqrt(1 - cos^2) loses precision near the normal.
    float sinI = glm::length(vec2(wo.x, wo.y)), sinT = glm::length(vec2(s.wi.x, s.wi.y));
    EXPECT_NEAR(etaI * sinI, etaT * sinT, 2e-6f);
    // Refracted ray stays in the plane of incidence, on the other side of the normal.
    EXPECT_NEAR(wo.x * s.wi.y - wo.y * s.wi.x, 0.0f, 1e-5f);
    EXPECT_LE(wo.x * s.wi.x + wo.y * s.wi.y, 1e-6f);
    EXPECT_FLOAT_EQ(s.eta, etaT / etaI);
    float weight = s.f.x * AbsCosTheta(s.wi) / s.pdf;
    EXPECT_NEAR(weight, 1.0f / (s.eta * s.eta), 1e-5f);  // radiance compression
  }
}

// Paths through a clear glass sphere in a uniform white environment all come back with weight
// exactly 1 (reflection weight 1, entering 1/eta^2, leaving eta^2): the sphere is invisible.
// Deterministic up to float round-off (intersection is analytic, no epsilons).
TEST(BsdfTest, GlassSphereIsInvisibleInUniformEnvironment) {
  Material m = Glass(1.5f);
  Uniform u(8);
  double maxError = 0.0;
  int trapped = 0;
  for (int i = 0; i < 20000; ++i) {
    vec2 disk = 0.9999f * SampleUniformDiskConcentric(u.Get2());  // no exactly tangent rays
    vec3 d(0, 0, 1);
    vec3 p(disk.x, disk.y, -std::sqrt(std::max(0.0f, 1.0f - glm::dot(disk, disk))));
    float throughput = 1.0f;
    bool escaped = false;
    for (int bounce = 0; bounce < 256 && !escaped; ++bounce) {
      vec3 n = glm::normalize(p);  // unit sphere at the origin: outward normal
      Frame frame = Frame::FromZ(n);
      BsdfSample s;
      if (!SampleBsdf(m, frame.ToLocal(-d), u(), u.Get2(), &s)) break;
      throughput *= s.f.x * AbsCosTheta(s.wi) / s.pdf;
      d = glm::normalize(frame.FromLocal(s.wi));
      if (glm::dot(d, n) > 0.0f) escaped = true;  // convex: an outgoing ray never returns
      else p = glm::normalize(p - 2.0f * glm::dot(p, d) * d);  // the chord's other end
    }
    if (!escaped) ++trapped;
    else maxError = std::max(maxError, std::fabs(double(throughput) - 1.0));
  }
  EXPECT_LT(maxError, 1e-4);
  // A sphere has no total internal reflection: every internal hit sees the entry angle, so a
  // path stays 256 bounces with probability R^255 (R at the entry angle), which is < 1e-9
  // unless the entry is within ~1e-5 of grazing (a fraction ~1e-5 of the disk): negligible.
  EXPECT_EQ(trapped, 0);
}

TEST(BsdfTest, EmissiveReflectsNothing) {
  Material emissive;
  emissive.type = MaterialType::kEmissive;
  emissive.radiance = vec3(5.0f);
  BsdfSample s;
  EXPECT_FALSE(SampleBsdf(emissive, vec3(0, 0, 1), 0.5f, vec2(0.5f), &s));
  EXPECT_TRUE(IsBlack(EvalBsdf(emissive, vec3(0, 0, 1), vec3(0, 0.6f, 0.8f))));
  EXPECT_EQ(PdfBsdf(emissive, vec3(0, 0, 1), vec3(0, 0.6f, 0.8f)), 0.0f);
  EXPECT_FALSE(HasNonDeltaLobe(emissive));
}

// pbrt-v4's rule: alpha = roughness^2 below 1e-3 is a delta lobe (roughness 0.0316).
TEST(BsdfTest, RoughnessDecidesWhichLobesAreDelta) {
  auto with = [](Material m, float roughness) {
    m.roughness = roughness;
    return m;
  };
  for (float r : {0.0f, 0.03f}) {
    EXPECT_FALSE(HasNonDeltaLobe(with(Conductor(vec3(0.9f)), r))) << r;
    EXPECT_FALSE(HasNonDeltaLobe(with(Glass(1.5f), r))) << r;
    BsdfSample s;
    ASSERT_TRUE(SampleBsdf(with(Conductor(vec3(0.9f)), r), vec3(0, 0.6f, 0.8f), 0.5f, vec2(0.3f), &s));
    EXPECT_TRUE(s.isDelta);
  }
  for (float r : {0.032f, 0.5f, 1.0f}) {
    EXPECT_TRUE(HasNonDeltaLobe(with(Conductor(vec3(0.9f)), r))) << r;
    EXPECT_TRUE(HasNonDeltaLobe(with(Conductor(vec3(0.0f)), r))) << r;  // Schlick: F(90) = 1
    EXPECT_TRUE(HasNonDeltaLobe(with(Glass(1.5f), r))) << r;
    EXPECT_FALSE(HasNonDeltaLobe(with(Glass(1.0f), r))) << r;  // index 1: light passes straight
  }
  Material plastic;
  plastic.type = MaterialType::kPlastic;
  plastic.ior = 1.5f;
  for (float r : {0.0f, 0.5f}) EXPECT_TRUE(HasNonDeltaLobe(with(plastic, r))) << r;  // the base
  EXPECT_TRUE(HasNonDeltaLobe(Diffuse(vec3(0.5f))));
  EXPECT_FALSE(HasNonDeltaLobe(Diffuse(vec3(0.0f))));
}

// Smooth plastic's coat is a mirror chosen with Mitsuba's probability; its weight is F / p.
TEST(BsdfTest, SmoothPlasticCoatIsAFresnelMirror) {
  Material m;
  m.type = MaterialType::kPlastic;
  m.albedo = vec3(0.6f, 0.3f, 0.1f);
  m.ior = 1.5f;
  float w = 1.0f / (1.0f + (0.6f + 0.3f + 0.1f) / 3.0f);  // m_specular_sampling_weight
  for (vec3 wo : TestDirections()) {
    float f = FresnelDielectric(fabsf(wo.z), 1.5f);
    float pCoat = f * w / (f * w + (1.0f - f) * (1.0f - w));
    BsdfSample s;
    ASSERT_TRUE(SampleBsdf(m, wo, 0.999f * pCoat, vec2(0.5f), &s));  // uc below pCoat: coat
    EXPECT_TRUE(s.isDelta);
    EXPECT_EQ(s.wi, vec3(-wo.x, -wo.y, wo.z));
    EXPECT_NEAR(s.pdf, pCoat, 1e-6f);
    EXPECT_NEAR(s.f.x * AbsCosTheta(s.wi) / s.pdf, f / pCoat, 1e-5f * f / pCoat);
    ASSERT_TRUE(SampleBsdf(m, wo, 0.5f * (1.0f + pCoat), vec2(0.3f, 0.6f), &s));  // the base
    EXPECT_FALSE(s.isDelta);
    EXPECT_TRUE(SameHemisphere(wo, s.wi));
  }
}

// Fdr (plastic's internal-reflection weighting) against double quadrature of 2 F(mu) mu dmu
// (midpoint rule, 2e5 intervals of a smooth integrand: error < 1e-9). Errors are the float
// closed form's (3e-6) above ior 1.05 and the d'Eon-Irving fit's below.
TEST(BsdfTest, FresnelDiffuseReflectanceMatchesQuadrature) {
  for (double eta : {1.02, 1.1, 1.33, 1.5, 2.0, 2.5, 4.0, 1 / 1.02, 1 / 1.33, 1 / 1.5, 1 / 2.5}) {
    const int n = 200000;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
      double mu = (i + 0.5) / n;
      sum += FresnelDielectric(float(mu), float(eta)) * mu;
    }
    double expect = 2.0 * sum / n;
    double tolerance = (eta < 1.05 && eta > 1 / 1.05) ? 2e-4 : 2e-5;
    EXPECT_NEAR(FresnelDiffuseReflectance(float(eta)), expect, tolerance) << "eta " << eta;
  }
}

}  // namespace
}  // namespace pt
