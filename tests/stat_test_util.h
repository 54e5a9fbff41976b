// Statistical hypothesis tests for sampling code (header-only, host-only):
//  - Pearson's chi-square goodness of fit of sampled directions against a pdf, binned in
//    spherical coordinates (theta x phi), expected counts by numerical integration of the pdf,
//    low-expectation bins pooled (after Mitsuba's / pbrt-v4's chi2 tests);
//  - the p-value from the regularised upper incomplete gamma function;
//  - an exact two-sided binomial test.
// Each test returns a p-value; asserting p > alpha has false-alarm probability alpha.
#pragma once

#include <random>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "src/core/math.h"
#include "tests/z_scores.h"

namespace pt::test {

// The alpha the tests assert p > alpha with: each assertion's false-alarm probability.
constexpr double kChiSquareAlpha = 1e-4;

// A uniformly distributed unit vector (normalised Gaussian triple).
inline vec3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<float> g;
  vec3 v;
  do v = vec3(g(rng), g(rng), g(rng));
  while (glm::dot(v, v) < 1e-6f);
  return glm::normalize(v);
}

// Fixed-seed uniform numbers in [0, 1) with 24 random bits (never 1), as the renderer's own.
struct Uniform {
  std::mt19937 rng;
  explicit Uniform(uint32_t seed) : rng(seed) {}
  float operator()() { return float(rng() >> 8) * 0x1p-24f; }
  vec2 Get2() {
    float a = (*this)();
    return vec2(a, (*this)());
  }
};


// ---- Regularised incomplete gamma (Numerical Recipes 6.2: series / Lentz continued fraction)

// P(a, x) by its series, valid (fast) for x < a + 1.
inline double GammaPSeries(double a, double x) {
  double ap = a, del = 1.0 / a, sum = del;
  for (int n = 0; n < 100000; ++n) {
    ap += 1.0;
    del *= x / ap;
    sum += del;
    if (std::fabs(del) < std::fabs(sum) * 1e-16) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Q(a, x) by its continued fraction, valid (fast) for x >= a + 1.
inline double GammaQContinuedFraction(double a, double x) {
  const double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    double del = d * c;
    h *= del;
    if (std::fabs(del - 1.0) < 1e-16) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

// Regularised upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0.
inline double RegularizedGammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  if (x < a + 1.0) return 1.0 - GammaPSeries(a, x);
  return GammaQContinuedFraction(a, x);
}

// P(chi^2_dof >= chi2): the chi-square distribution's upper tail.
inline double ChiSquarePValue(double chi2, int dof) {
  return RegularizedGammaQ(0.5 * dof, 0.5 * chi2);
}

// ---- Exact two-sided binomial test ----

// log of the Binomial(n, p) probability of k successes.
inline double LogBinomialPmf(int64_t n, int64_t k, double p) {
  double logChoose = std::lgamma(double(n) + 1) - std::lgamma(double(k) + 1) -
                     std::lgamma(double(n - k) + 1);
  double a = k > 0 ? double(k) * std::log(p) : 0.0;
  double b = n - k > 0 ? double(n - k) * std::log1p(-p) : 0.0;
  return logChoose + a + b;
}

// Two-sided p-value of observing k successes in n trials of probability p: twice the smaller
// tail, P(X <= k) or P(X >= k), capped at 1. Tails are summed exactly (O(n), fine for n ~ 1e6).
inline double BinomialTwoSidedPValue(int64_t n, int64_t k, double p) {
  if (p <= 0.0) return k == 0 ? 1.0 : 0.0;
  if (p >= 1.0) return k == n ? 1.0 : 0.0;
  double lower = 0.0, upper = 0.0;
  for (int64_t i = 0; i <= k; ++i) lower += std::exp(LogBinomialPmf(n, i, p));
  for (int64_t i = k; i <= n; ++i) upper += std::exp(LogBinomialPmf(n, i, p));
  return std::min(1.0, 2.0 * std::min(lower, upper));
}

// ---- Chi-square goodness of fit of directions ----

struct ChiSquareOptions {
  int thetaBins = 16;     // over [0, pi]
  int phiBins = 32;       // over [0, 2 pi)
  int integration = 8;    // Simpson sub-intervals per bin and axis (even)
  int refine = 0;         // > integration: sub-intervals for bins where the pdf jumps (even)
  double minExpected = 5; // bins expecting fewer samples are pooled
};

struct ChiSquareResult {
  double pValue = 0.0;
  double chi2 = 0.0;
  int dof = 0;
  std::string message;  // why it failed outright, or a summary
};

// Draws one direction (unit, any frame) or returns false for "no sample" (the pdf then
// integrates to less than 1 and the shortfall is the expected count of the failure cell).
using DirectionSampler = std::function<bool(pt::vec3* w)>;
using DirectionPdf = std::function<double(pt::vec3 w)>;

inline pt::vec3 SphericalToDirection(double theta, double phi) {
  double s = std::sin(theta);
  return pt::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(std::cos(theta)));
}

// Composite Simpson's rule of pdf * sin(theta) over one bin with m x m sub-intervals; also
// reports the smallest and largest pdf value it saw.
inline double IntegrateBin(const DirectionPdf& pdf, double theta0, double phi0, double dTheta,
                           double dPhi, int m, double* minPdf, double* maxPdf) {
  double hTheta = dTheta / m, hPhi = dPhi / m, sum = 0.0;
  auto weight = [m](int i) { return (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0); };
  *minPdf = INFINITY;
  *maxPdf = -INFINITY;
  for (int i = 0; i <= m; ++i) {
    double theta = theta0 + i * hTheta;
    for (int j = 0; j <= m; ++j) {
      double value = pdf(SphericalToDirection(theta, phi0 + j * hPhi));
      *minPdf = std::min(*minPdf, value);
      *maxPdf = std::max(*maxPdf, value);
      sum += weight(i) * weight(j) * value * std::sin(theta);
    }
  }
  return sum * hTheta * hPhi / 9.0;
}

// Expected probability of each (theta, phi) bin. Simpson's rule converges only linearly
// across a discontinuity (a light's outline), so with o.refine > 0 a bin whose pdf samples
// vary by more than 1% is integrated again with o.refine sub-intervals per axis.
inline std::vector<double> IntegratePdfOverBins(const DirectionPdf& pdf,
                                                const ChiSquareOptions& o) {
  std::vector<double> prob(size_t(o.thetaBins) * o.phiBins, 0.0);
  double dTheta = M_PI / o.thetaBins, dPhi = 2.0 * M_PI / o.phiBins;
  for (int t = 0; t < o.thetaBins; ++t) {
    for (int p = 0; p < o.phiBins; ++p) {
      double lo, hi;
      double v = IntegrateBin(pdf, t * dTheta, p * dPhi, dTheta, dPhi, o.integration, &lo, &hi);
      if (o.refine > o.integration && hi - lo > 0.01 * hi)
        v = IntegrateBin(pdf, t * dTheta, p * dPhi, dTheta, dPhi, o.refine, &lo, &hi);
      prob[size_t(t) * o.phiBins + p] = v;
    }
  }
  return prob;
}

// Index of the bin a unit direction falls in.
inline size_t DirectionBin(pt::vec3 w, const ChiSquareOptions& o) {
  double z = std::clamp(double(w.z), -1.0, 1.0);
  double theta = std::acos(z);
  double phi = std::atan2(double(w.y), double(w.x));
  if (phi < 0.0) phi += 2.0 * M_PI;
  int t = std::min(o.thetaBins - 1, int(theta / M_PI * o.thetaBins));
  int p = std::min(o.phiBins - 1, int(phi / (2.0 * M_PI) * o.phiBins));
  return size_t(t) * o.phiBins + p;
}

// Pearson's statistic over observed / expected counts, pooling bins with expected count below
// minExpected (smallest first) until the pool reaches it. A bin that expects nothing but
// receives more than 1e-5 of the samples fails outright (p = 0): the sampler puts mass where
// the pdf says there is none. (Fewer are tolerated as round-off at bin edges, as pbrt does.)
inline ChiSquareResult PearsonChiSquare(const std::vector<double>& observed,
                                        const std::vector<double>& expected, double total,
                                        double minExpected) {
  ChiSquareResult r;
  std::vector<size_t> order(observed.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pooledObs = 0.0, pooledExp = 0.0;
  int cells = 0;
  for (size_t i : order) {
    if (expected[i] <= 0.0) {
      if (observed[i] > total * 1e-5) {
        std::ostringstream msg;
        msg << observed[i] << " samples in bin " << i << " whose expected count is 0";
        r.message = msg.str();
        return r;
      }
    } else if (expected[i] < minExpected || (pooledExp > 0.0 && pooledExp < minExpected)) {
      pooledObs += observed[i];
      pooledExp += expected[i];
    } else {
      double diff = observed[i] - expected[i];
      r.chi2 += diff * diff / expected[i];
      ++cells;
    }
  }
  if (pooledExp > 0.0) {
    double diff = pooledObs - pooledExp;
    r.chi2 += diff * diff / pooledExp;
    ++cells;
  }
  r.dof = cells - 1;
  if (r.dof < 1) {
    r.message = "fewer than 2 cells after pooling";
    return r;
  }
  r.pValue = ChiSquarePValue(r.chi2, r.dof);
  std::ostringstream msg;
  msg << "chi2 = " << r.chi2 << ", dof = " << r.dof << ", p = " << r.pValue;
  r.message = msg.str();
  return r;
}

// Chi-square test of sampleCount draws of `sample` against `pdf` (per unit solid angle).
inline ChiSquareResult ChiSquareDirections(const DirectionSampler& sample,
                                           const DirectionPdf& pdf, int64_t sampleCount,
                                           const ChiSquareOptions& o = {}) {
  std::vector<double> prob = IntegratePdfOverBins(pdf, o);
  size_t bins = prob.size();
  std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
  for (int64_t i = 0; i < sampleCount; ++i) {
    pt::vec3 w;
    if (sample(&w)) observed[DirectionBin(w, o)] += 1.0;
    else observed[bins] += 1.0;  // the failure cell
  }
  double mass = 0.0;
  for (size_t b = 0; b < bins; ++b) {
    expected[b] = prob[b] * double(sampleCount);
    mass += prob[b];
  }
  // Failure cell: what the pdf leaves of 1 (integration error makes this ~1e-6, pooled away).
  expected[bins] = std::max(0.0, 1.0 - mass) * double(sampleCount);
  return PearsonChiSquare(observed, expected, double(sampleCount), o.minExpected);
}

// ---- Means with variance-derived tolerances ----


struct MeanEstimate {
  double mean = 0.0;
  double stdError = 0.0;  // sample standard deviation / sqrt(n)
};

// Running mean and standard error (Welford), for CLT-based tolerances z * sigma / sqrt(n).
struct MeanAccumulator {
  int64_t n = 0;
  double mean = 0.0, m2 = 0.0;
  void Add(double x) {
    ++n;
    double d = x - mean;
    mean += d / double(n);
    m2 += d * (x - mean);
  }
  MeanEstimate Result() const {
    double var = n > 1 ? m2 / double(n - 1) : 0.0;
    return {mean, std::sqrt(var / double(n))};
  }
};

}  // namespace pt::test
