// The GGX distribution (src/materials/microfacet.h): D and Lambda against their textbook forms,
// D normalised over projected area, the visible-normal density normalised (Monte Carlo), and
// Heitz's visible-normal sampling against that density (chi-square). Then the GGX lobes of
// bsdf.h: rough conductor (both sides) and rough dielectric (outside and inside) sample
// exactly PdfBsdf (chi-square), and each sample's f and pdf are EvalBsdf's and PdfBsdf's.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <sstream>

#include "src/materials/bsdf.h"
#include "src/materials/microfacet.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

constexpr double kAlpha = 1e-4;  // per-assertion false-alarm probability

struct Uniform {
  std::mt19937 rng;
  explicit Uniform(uint32_t seed) : rng(seed) {}
  float operator()() { return float(rng() >> 8) * 0x1p-24f; }  // [0, 1), never 1
  vec2 Get2() {
    float a = (*this)();
    return vec2(a, (*this)());
  }
};

vec3 Spherical(double theta, double phi) { return test::SphericalToDirection(theta, phi); }

// Viewing directions on both sides, normal to near-grazing.
std::vector<vec3> Views() {
  return {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
          glm::normalize(vec3(0.5f, 0.7f, 0.2f)), glm::normalize(vec3(-0.99f, 0.0f, 0.08f)),
          glm::normalize(vec3(0.3f, -0.4f, -0.866f))};
}

// ---- Chi-square with bin probabilities from interior nodes ----
// stat_test_util.h integrates each bin with Simpson nodes on its edges; a lobe cut off at the
// horizon (any GGX reflection: its density does not vanish there) is then evaluated on the
// horizon for the bins below it too, which expect samples they never get. Gauss-Legendre
// nodes lie strictly inside each bin, and bins whose density varies are subdivided.

struct GaussRule {
  std::vector<double> x, w;  // on [0, 1]
};

GaussRule GaussLegendre(int n) {
  GaussRule r{std::vector<double>(n), std::vector<double>(n)};
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), p0 = 1, dp = 1;
    for (int iter = 0; iter < 100; ++iter) {  // Newton on P_n via the recurrence
      double p1 = 0;
      p0 = 1;
      for (int k = 1; k <= n; ++k) {
        double p2 = p1;
        p1 = p0;
        p0 = ((2 * k - 1) * z * p1 - (k - 1) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1);
      double dz = p0 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-15) break;
    }
    r.x[i] = 0.5 * (1 - z);
    r.w[i] = 1 / ((1 - z * z) * dp * dp);  // half of the [-1, 1] weight
  }
  return r;
}

// Integral of pdf sin(theta) over one (theta, phi) cell; reports the pdf's range.
double IntegrateCell(const test::DirectionPdf& pdf, double t0, double p0, double dt, double dp,
                     const GaussRule& g, double* lo, double* hi) {
  double sum = 0;
  for (size_t i = 0; i < g.x.size(); ++i) {
    double theta = t0 + g.x[i] * dt;
    for (size_t j = 0; j < g.x.size(); ++j) {
      double v = pdf(Spherical(theta, p0 + g.x[j] * dp));
      *lo = std::min(*lo, v);
      *hi = std::max(*hi, v);
      sum += g.w[i] * g.w[j] * v * std::sin(theta);
    }
  }
  return sum * dt * dp;
}

struct ChiSquareGrid {
  int thetaBins = 16, phiBins = 32;
  int subdivide = 4;  // cells per axis in a bin that needs them
};

// Probability of one bin: 4 x 4 nodes, or subdivided into cells of 6 x 6 nodes where the
// density varies by more than 1% or where samples landed (a lobe narrower than the node
// spacing can fall between the coarse nodes; samples show where it is). Either way the
// result is the bin's integral, so the choice does not bias the test, only sharpens it.
double BinProbability(const test::DirectionPdf& pdf, size_t b, const test::ChiSquareOptions& o,
                      int subdivide, bool sampled, double refineAbove) {
  static const GaussRule coarse = GaussLegendre(4), fine = GaussLegendre(6);
  double dt = M_PI / o.thetaBins, dp = 2 * M_PI / o.phiBins;
  double t0 = double(b / o.phiBins) * dt, p0 = double(b % o.phiBins) * dp;
  double lo = INFINITY, hi = -INFINITY;
  double v = IntegrateCell(pdf, t0, p0, dt, dp, coarse, &lo, &hi);
  if (!sampled && !(hi - lo > 0.01 * hi && v > refineAbove)) return v;
  int s = subdivide;
  v = 0;
  for (int i = 0; i < s * s; ++i)
    v += IntegrateCell(pdf, t0 + (i / s) * dt / s, p0 + (i % s) * dp / s, dt / s, dp / s, fine,
                       &lo, &hi);
  return v;
}

test::ChiSquareResult ChiSquareInterior(const test::DirectionSampler& sample,
                                        const test::DirectionPdf& pdf, int64_t n,
                                        const ChiSquareGrid& grid) {
  test::ChiSquareOptions o;
  o.thetaBins = grid.thetaBins;
  o.phiBins = grid.phiBins;
  size_t bins = size_t(o.thetaBins) * o.phiBins;
  std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
  for (int64_t i = 0; i < n; ++i) {
    vec3 w;
    if (sample(&w)) observed[test::DirectionBin(w, o)] += 1.0;
    else observed[bins] += 1.0;  // the failure cell
  }
  double mass = 0;
  for (size_t b = 0; b < bins; ++b) {
    double v = BinProbability(pdf, b, o, grid.subdivide, observed[b] > 0, 0.1 / double(n));
    expected[b] = v * double(n);
    mass += v;
  }
  // The failure cell expects what the pdf leaves of 1. Integration error (~1e-5 for the
  // narrowest lobes) can exceed a genuine failure rate that small, so it is never "expects
  // nothing" (an outright failure): it joins the pool of small cells instead.
  expected[bins] = std::max(1.0 - mass, 1e-9) * double(n);
  return test::PearsonChiSquare(observed, expected, double(n), o.minExpected);
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
      test::ChiSquareResult r = ChiSquareInterior(sample, pdf, 200000, grid);
      // Chi-square goodness of fit: false-alarm probability kAlpha = 1e-4 per case.
      EXPECT_GT(r.pValue, kAlpha) << "alpha " << alpha << " w.z " << w.z << ": " << r.message;
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

// Finer bins, and finer cells in them, for narrow lobes.
ChiSquareGrid GridFor(float roughness) {
  ChiSquareGrid g;
  if (roughness < 0.2f) {
    g.thetaBins = 48;
    g.phiBins = 96;
    g.subdivide = 8;
  }
  return g;
}

// Largest relative difference of a and b over the channels (absolute below 1e-6).
float RelativeDifference(vec3 a, vec3 b) {
  float worst = 0.0f;
  for (int c = 0; c < 3; ++c)
    worst = std::max(worst, fabsf(a[c] - b[c]) / std::max(1e-6f, std::max(fabsf(a[c]), fabsf(b[c]))));
  return worst;
}

// The sample's own f and pdf (computed from the sampled microfacet) agree with EvalBsdf and
// PdfBsdf of its direction (which rebuild the half vector) up to float round-off; so does the
// path weight f |cos| / pdf. 2e-3 covers the half vector rebuilt from a refracted direction
// at alpha = 0.01, where D is most sensitive to it.
constexpr float kConsistency = 2e-3f;

struct LobeCheck {
  int samples = 0, mismatches = 0;
  float worst = 0.0f;
};

void CheckLobe(const Material& m, vec3 wo, uint32_t seed, int64_t n) {
  Uniform u(seed);
  LobeCheck c;
  auto sample = [&](vec3* w) {
    BsdfSample s;
    if (!SampleBsdf(m, wo, u(), u.Get2(), &s)) return false;
    EXPECT_FALSE(s.isDelta);
    EXPECT_EQ(s.isTransmission, s.wi.z * wo.z < 0.0f);
    vec3 f = EvalBsdf(m, wo, s.wi);
    float pdf = PdfBsdf(m, wo, s.wi);
    vec3 weight = s.f * (AbsCosTheta(s.wi) / s.pdf);
    vec3 expect = pdf > 0.0f ? f * (AbsCosTheta(s.wi) / pdf) : vec3(-1.0f);
    float d = std::max({RelativeDifference(weight, expect), RelativeDifference(s.f, f),
                        fabsf(s.pdf - pdf) / std::max(s.pdf, pdf)});
    c.worst = std::max(c.worst, d);
    ++c.samples;
    if (d > kConsistency) ++c.mismatches;
    *w = s.wi;
    return true;
  };
  auto pdf = [&](vec3 w) { return double(PdfBsdf(m, wo, w)); };
  test::ChiSquareResult r = ChiSquareInterior(sample, pdf, n, GridFor(m.roughness));
  std::ostringstream what;
  what << "type " << int(m.type) << " roughness " << m.roughness << " ior " << m.ior
       << " wo = (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
  // Chi-square goodness of fit: false-alarm probability kAlpha = 1e-4 per case.
  EXPECT_GT(r.pValue, kAlpha) << what.str() << ": " << r.message;
  // Deterministic up to round-off: no sample may disagree.
  EXPECT_EQ(c.mismatches, 0) << what.str() << ": worst relative difference " << c.worst;
  EXPECT_GT(c.samples, 0) << what.str();
}

TEST(RoughConductorTest, SamplingMatchesPdfOnBothSides) {
  uint32_t seed = 400;
  for (float roughness : {0.1f, 0.3f, 0.6f, 1.0f}) {
    Material m = RoughConductor(vec3(0.95f, 0.64f, 0.54f), roughness);
    ASSERT_TRUE(HasNonDeltaLobe(m));
    for (vec3 wo : Views()) CheckLobe(m, wo, seed++, 200000);
  }
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
    if (!SameHemisphere(a, b)) EXPECT_TRUE(IsBlack(fab));
  }
}

TEST(RoughDielectricTest, SamplingMatchesPdfOutsideAndInside) {
  uint32_t seed = 500;
  // Inside views include one past the critical angle of both indices (total internal
  // reflection of most microfacets).
  std::vector<vec3> views = {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
                             glm::normalize(vec3(0.9f, 0.3f, 0.15f)),
                             glm::normalize(vec3(0.2f, 0.1f, -1.0f)),
                             glm::normalize(vec3(0.5f, -0.3f, -0.6f)),
                             glm::normalize(vec3(0.85f, 0.3f, -0.3f))};
  for (float ior : {1.33f, 1.5f, 2.4f}) {
    for (float roughness : {0.1f, 0.3f, 0.6f}) {
      if (ior == 2.4f && roughness != 0.3f) continue;  // one case of a high index suffices
      Material m = RoughGlass(ior, roughness);
      ASSERT_TRUE(HasNonDeltaLobe(m));
      for (vec3 wo : views) CheckLobe(m, wo, seed++, 150000);
    }
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

}  // namespace
}  // namespace pt
