// The statistics the GPU agreement tests decide by (tests/welch.h), checked where no GPU is
// needed: identical samples give p = 1, a shift of 10 standard errors gives p far below 1e-3,
// and the binomial bound of Binomial(64, 0.01) at 1e-3 is 4 (P(X > 4) = 4.6e-4, P(X > 3) =
// 3.6e-3).
#include <gtest/gtest.h>

#include <vector>

#include "tests/welch.h"

namespace pt::test {
namespace {

TEST(Welch, WelchAndBinomialHelpersAreCalibrated) {
  std::vector<double> a{1, 2, 3, 4, 5, 6, 7, 8}, b = a;
  EXPECT_NEAR(WelchPValue(a, b), 1.0, 1e-12);
  for (double& x : b) x += 10.0;
  EXPECT_LT(WelchPValue(a, b), 1e-3);
  EXPECT_EQ(BinomialUpperBound(64, 0.01, 1e-3), 4);
}

}  // namespace
}  // namespace pt::test
