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
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;

constexpr double kAlpha = 1e-4;  // per-assertion false-alarm probability

using test::Uniform;

vec3 Spherical(double theta, double phi) { return test::SphericalToDirection(theta, phi); }

// Viewing directions on both sides, normal to near-grazing.
std::vector<vec3> Views() {
  return {vec3(0, 0, 1), glm::normalize(vec3(0.6f, 0.0f, 0.8f)),
          glm::normalize(vec3(0.5f, 0.7f, 0.2f)), glm::normalize(vec3(-0.99f, 0.0f, 0.08f)),
          glm::normalize(vec3(0.3f, -0.4f, -0.866f))};
}

// ---- Chi-square with accurate bin probabilities ----
// stat_test_util.h integrates each bin with Simpson nodes on its edges and a fixed
// refinement. GGX lobes need more: a reflection lobe is cut off at the horizon without
// vanishing there (edge nodes then give the bins below it mass they never receive), a lobe of
// alpha = 0.01 is narrower than the nodes, and rough transmission stops abruptly where the
// half vector it needs would face below the horizon (wi.z = -wo.z / etap: microfacets have
// wm.z > 0), a jump inside the sphere. So here: Gauss-Legendre nodes strictly inside each
// cell, adaptive subdivision until halves agree, and known jumps in theta as cell edges.

// 5-point Gauss-Legendre rule on [0, 1] (nodes (1 + x) / 2, weights w / 2 of the [-1, 1] rule).
constexpr double kGaussX[5] = {0.0469100770306680, 0.2307653449471585, 0.5,
                               0.7692346550528415, 0.9530899229693320};
constexpr double kGaussW[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444,
                               0.2393143352496832, 0.1184634425280945};

struct Cell {
  double t0, p0, dt, dp;  // theta and phi ranges
};

// Integral of pdf sin(theta) over a cell, 5 x 5 nodes.
double IntegrateCell(const test::DirectionPdf& pdf, const Cell& c) {
  double sum = 0;
  for (int i = 0; i < 5; ++i) {
    double theta = c.t0 + kGaussX[i] * c.dt;
    for (int j = 0; j < 5; ++j)
      sum += kGaussW[i] * kGaussW[j] * pdf(Spherical(theta, c.p0 + kGaussX[j] * c.dp)) *
             std::sin(theta);
  }
  return sum * c.dt * c.dp;
}

// Splits into quarters until they agree with the whole within tol (halved per level).
double IntegrateAdaptive(const test::DirectionPdf& pdf, const Cell& c, double whole, double tol,
                         int depth) {
  Cell q[4];
  double part[4], sum = 0;
  for (int k = 0; k < 4; ++k) {
    q[k] = {c.t0 + (k / 2) * c.dt / 2, c.p0 + (k % 2) * c.dp / 2, c.dt / 2, c.dp / 2};
    part[k] = IntegrateCell(pdf, q[k]);
    sum += part[k];
  }
  if (depth == 0 || std::fabs(sum - whole) <= tol) return sum;
  double refined = 0;
  for (int k = 0; k < 4; ++k) refined += IntegrateAdaptive(pdf, q[k], part[k], tol / 2, depth - 1);
  return refined;
}

struct ChiSquareGrid {
  int thetaBins = 16, phiBins = 32;
  int startCells = 2;               // cells per axis before adapting
  std::vector<double> thetaBreaks;  // where the density may jump (cell edges there)
};

// Probability of one bin: its theta range split at the breaks, each piece in startCells^2
// cells refined adaptively to within 0.01 expected samples per bin.
double BinProbability(const test::DirectionPdf& pdf, double t0, double p0,
                      const test::ChiSquareOptions& o, const ChiSquareGrid& grid, int64_t n) {
  double dt = M_PI / o.thetaBins, dp = 2 * M_PI / o.phiBins;
  std::vector<double> edges = {t0};
  for (double b : grid.thetaBreaks)
    if (b > t0 && b < t0 + dt) edges.push_back(b);
  edges.push_back(t0 + dt);
  int s = grid.startCells;
  double tol = 0.01 / double(n) / (s * s * (edges.size() - 1)), sum = 0;
  for (size_t e = 0; e + 1 < edges.size(); ++e) {
    double h = (edges[e + 1] - edges[e]) / s;
    for (int i = 0; i < s * s; ++i) {
      Cell c{edges[e] + (i / s) * h, p0 + (i % s) * dp / s, h, dp / s};
      sum += IntegrateAdaptive(pdf, c, IntegrateCell(pdf, c), tol, 6);
    }
  }
  return sum;
}

test::ChiSquareResult ChiSquareAccurate(const test::DirectionSampler& sample,
                                        const test::DirectionPdf& pdf, int64_t n,
                                        const ChiSquareGrid& grid) {
  test::ChiSquareOptions o;
  o.thetaBins = grid.thetaBins;
  o.phiBins = grid.phiBins;
  size_t bins = size_t(o.thetaBins) * o.phiBins;
  std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
  double mass = 0;
  for (size_t b = 0; b < bins; ++b) {
    double v = BinProbability(pdf, double(b / o.phiBins) * M_PI / o.thetaBins,
                              double(b % o.phiBins) * 2 * M_PI / o.phiBins, o, grid, n);
    expected[b] = v * double(n);
    mass += v;
  }
  for (int64_t i = 0; i < n; ++i) {
    vec3 w;
    if (sample(&w)) observed[test::DirectionBin(w, o)] += 1.0;
    else observed[bins] += 1.0;  // the failure cell
  }
  // The failure cell expects what the pdf leaves of 1. Integration error can exceed a genuine
  // failure rate of ~1e-5, so it never "expects nothing" (an outright failure): it joins the
  // pool of small cells instead, where the chi-square still weighs it.
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
      test::ChiSquareResult r = ChiSquareAccurate(sample, pdf, 100000, grid);
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

// Finer bins for narrow lobes; rough transmission's jump where wi.z = -wo.z / etap.
ChiSquareGrid GridFor(const Material& m, vec3 wo) {
  ChiSquareGrid g;
  if (m.roughness < 0.2f) {
    g.thetaBins = 48;
    g.phiBins = 96;
    g.startCells = 1;
  }
  if (m.type == MaterialType::kDielectric) {
    float etap = wo.z > 0.0f ? m.ior : 1.0f / m.ior;
    float z = -wo.z / etap;
    if (fabsf(z) < 1.0f) g.thetaBreaks.push_back(std::acos(double(z)));
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

// The sample's path weight f |cos| / pdf (from the sampled microfacet) equals EvalBsdf |cos| /
// PdfBsdf of its direction (which rebuild the half vector) up to float round-off. f and pdf
// alone agree less closely: near the critical angle 1 - F(wo.wm) is steep (a square root),
// so the rebuilt microfacet's round-off moves both, by the same factor.
constexpr float kWeightConsistency = 1e-3f;
constexpr float kValueConsistency = 1e-2f;

struct LobeCheck {
  int samples = 0, mismatches = 0;
  float worstWeight = 0.0f, worstValue = 0.0f;
  void Add(const Material& m, vec3 wo, const BsdfSample& s) {
    vec3 f = EvalBsdf(m, wo, s.wi);
    float pdf = PdfBsdf(m, wo, s.wi);
    vec3 weight = s.f * (AbsCosTheta(s.wi) / s.pdf);
    vec3 expect = pdf > 0.0f ? f * (AbsCosTheta(s.wi) / pdf) : vec3(-1.0f);
    float dw = RelativeDifference(weight, expect);
    float dv = std::max(RelativeDifference(s.f, f), fabsf(s.pdf - pdf) / std::max(s.pdf, pdf));
    worstWeight = std::max(worstWeight, dw);
    worstValue = std::max(worstValue, dv);
    ++samples;
    if (dw > kWeightConsistency || dv > kValueConsistency) ++mismatches;
  }
};

// Chi-square of SampleBsdf against PdfBsdf for one material and wo (failed samples are the
// pdf's missing mass: shadowed or absorbed), with every sample checked by LobeCheck.
void CheckLobe(const Material& m, vec3 wo, uint32_t seed, int64_t n) {
  Uniform u(seed);
  LobeCheck c;
  auto sample = [&](vec3* w) {
    BsdfSample s;
    if (!SampleBsdf(m, wo, u(), u.Get2(), &s)) return false;
    if (s.isDelta) return false;  // smooth plastic's coat: the mass the pdf leaves out
    EXPECT_EQ(s.isTransmission, s.wi.z * wo.z < 0.0f);
    c.Add(m, wo, s);
    *w = s.wi;
    return true;
  };
  auto pdf = [&](vec3 w) { return double(PdfBsdf(m, wo, w)); };
  test::ChiSquareResult r = ChiSquareAccurate(sample, pdf, n, GridFor(m, wo));
  std::ostringstream what;
  what << "type " << int(m.type) << " roughness " << m.roughness << " ior " << m.ior
       << " wo = (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
  // Chi-square goodness of fit: false-alarm probability kAlpha = 1e-4 per case.
  EXPECT_GT(r.pValue, kAlpha) << what.str() << ": " << r.message;
  // Deterministic up to round-off: no sample may disagree.
  EXPECT_EQ(c.mismatches, 0) << what.str() << ": worst relative differences " << c.worstWeight
                             << " (weight), " << c.worstValue << " (f, pdf)";
  EXPECT_GT(c.samples, 0) << what.str();
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
