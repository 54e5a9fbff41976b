// Welch's unequal-variance t-test and the binomial tail, for comparing backends' renders.
#pragma once

#include <cmath>
#include <vector>

namespace pt::test {

// Regularised incomplete beta I_x(a, b), by its continued fraction (modified Lentz).
inline double IncompleteBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - IncompleteBeta(b, a, 1.0 - x);
  double lnFront = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                   b * std::log(1.0 - x);
  const double kTiny = 1e-300;
  double f = 1.0, c = 1.0, d = 0.0;
  for (int i = 0; i <= 400; ++i) {
    int m = i / 2;
    double num;
    if (i == 0) num = 1.0;
    else if (i % 2 == 0) num = (m * (b - m) * x) / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
    else num = -((a + m) * (a + b + m) * x) / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
    d = 1.0 + num * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    d = 1.0 / d;
    c = 1.0 + num / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    f *= c * d;
    if (std::fabs(1.0 - c * d) < 1e-12) break;
  }
  return std::exp(lnFront) * (f - 1.0) / a;
}

// Two-sided p-value of Welch's t for samples a and b.
inline double WelchPValue(const std::vector<double>& a, const std::vector<double>& b) {
  auto meanVar = [](const std::vector<double>& v, double* mean, double* var) {
    double m = 0.0;
    for (double x : v) m += x;
    m /= v.size();
    double s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    *mean = m;
    *var = s / (v.size() - 1);
  };
  double ma, va, mb, vb;
  meanVar(a, &ma, &va);
  meanVar(b, &mb, &vb);
  double sa = va / a.size(), sb = vb / b.size();
  if (sa + sb == 0.0) return ma == mb ? 1.0 : 0.0;
  double t = (ma - mb) / std::sqrt(sa + sb);
  double df = (sa + sb) * (sa + sb) /
              (sa * sa / (a.size() - 1) + sb * sb / (b.size() - 1));
  return IncompleteBeta(df / 2.0, 0.5, df / (df + t * t));
}

// The smallest m with P(X > m) <= alpha for X ~ Binomial(n, p).
inline int BinomialUpperBound(int n, double p, double alpha) {
  double cdf = 0.0;
  for (int k = 0; k <= n; ++k) {
    double lnPmf = std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) +
                   k * std::log(p) + (n - k) * std::log1p(-p);
    cdf += std::exp(lnPmf);
    if (1.0 - cdf <= alpha) return k;
  }
  return n;
}

// Blocks (a[k][i]: seed k, block i) whose Welch p-value between a and b is below alpha.
inline int FailingBlocks(const std::vector<std::vector<double>>& a,
                         const std::vector<std::vector<double>>& b, double alpha) {
  int failing = 0;
  for (size_t i = 0; i < a[0].size(); ++i) {
    std::vector<double> x, y;
    for (size_t k = 0; k < a.size(); ++k) x.push_back(a[k][i]);
    for (size_t k = 0; k < b.size(); ++k) y.push_back(b[k][i]);
    if (WelchPValue(x, y) < alpha) ++failing;
  }
  return failing;
}

}  // namespace pt::test
