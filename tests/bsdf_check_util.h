// Checks of BSDF lobes shared by the microfacet and glTF material tests: chi-square of
// sampled directions with accurate bin probabilities (below), and per-sample consistency of a
// sample's f and pdf with EvalBsdf and PdfBsdf of its direction.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "src/materials/bsdf.h"
#include "tests/stat_test_util.h"

namespace pt::test {

inline vec3 Spherical(double theta, double phi) { return SphericalToDirection(theta, phi); }

// ---- Chi-square with accurate bin probabilities ----
// stat_test_util.h integrates each bin with Simpson nodes on its edges and a fixed
// refinement. GGX lobes need more: a reflection lobe is cut off at the horizon without
// vanishing there (edge nodes then give the bins below it mass they never receive), a lobe of
// alpha = 0.01 is narrower than the nodes, and rough transmission stops abruptly where the
// half vector it needs would face below the horizon (wi.z = -wo.z / etap: microfacets have
// wm.z > 0), a jump inside the sphere. So here: Gauss-Legendre nodes strictly inside each
// cell, adaptive subdivision until halves agree, and known jumps in theta as cell edges.

// 5-point Gauss-Legendre rule on [0, 1] (nodes (1 + x) / 2, weights w / 2 of the [-1, 1] rule).
inline constexpr double kGaussX[5] = {0.0469100770306680, 0.2307653449471585, 0.5,
                               0.7692346550528415, 0.9530899229693320};
inline constexpr double kGaussW[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444,
                               0.2393143352496832, 0.1184634425280945};

struct Cell {
  double t0, p0, dt, dp;  // theta and phi ranges
};

// Integral of pdf sin(theta) over a cell, 5 x 5 nodes.
inline double IntegrateCell(const DirectionPdf& pdf, const Cell& c) {
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
inline double IntegrateAdaptive(const DirectionPdf& pdf, const Cell& c, double whole, double tol,
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
inline double BinProbability(const DirectionPdf& pdf, double t0, double p0,
                      const ChiSquareOptions& o, const ChiSquareGrid& grid, int64_t n) {
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

inline ChiSquareResult ChiSquareAccurate(const DirectionSampler& sample,
                                        const DirectionPdf& pdf, int64_t n,
                                        const ChiSquareGrid& grid) {
  ChiSquareOptions o;
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
    if (sample(&w)) observed[DirectionBin(w, o)] += 1.0;
    else observed[bins] += 1.0;  // the failure cell
  }
  // The failure cell expects what the pdf leaves of 1. Integration error can exceed a genuine
  // failure rate of ~1e-5, so it never "expects nothing" (an outright failure): it joins the
  // pool of small cells instead, where the chi-square still weighs it.
  expected[bins] = std::max(1.0 - mass, 1e-9) * double(n);
  return PearsonChiSquare(observed, expected, double(n), o.minExpected);
}

// Finer bins for narrow lobes; rough transmission's jump where wi.z = -wo.z / etap.
inline ChiSquareGrid GridFor(const Material& m, vec3 wo) {
  ChiSquareGrid g;
  if (m.roughness < 0.2f) {
    g.thetaBins = 48;
    g.phiBins = 96;
    g.startCells = 1;
  }
  bool volume = m.type == MaterialType::kGltfPbr && m.transmission > 0.0f &&
                !(m.flags & kMaterialThinWalled);
  if (m.type == MaterialType::kDielectric || volume) {
    float etap = wo.z > 0.0f ? m.ior : 1.0f / m.ior;
    float z = -wo.z / etap;
    if (fabsf(z) < 1.0f) g.thetaBreaks.push_back(std::acos(double(z)));
  }
  return g;
}

// Largest relative difference of a and b over the channels (absolute below 1e-6).
inline float RelativeDifference(vec3 a, vec3 b) {
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
inline void CheckLobe(const Material& m, vec3 wo, uint32_t seed, int64_t n) {
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
  ChiSquareResult r = ChiSquareAccurate(sample, pdf, n, GridFor(m, wo));
  std::ostringstream what;
  what << "type " << int(m.type) << " roughness " << m.roughness << " ior " << m.ior
       << " wo = (" << wo.x << ", " << wo.y << ", " << wo.z << ")";
  // Chi-square goodness of fit: false-alarm probability 1e-4 per case.
  EXPECT_GT(r.pValue, kChiSquareAlpha) << what.str() << ": " << r.message;
  // Deterministic up to round-off: no sample may disagree.
  EXPECT_EQ(c.mismatches, 0) << what.str() << ": worst relative differences " << c.worstWeight
                             << " (weight), " << c.worstValue << " (f, pdf)";
  EXPECT_GT(c.samples, 0) << what.str();
}

}  // namespace pt::test
