// Two-sided normal quantiles shared by the statistical tests: z such that P(|Z| > z) = p.
#pragma once

namespace pt::test {

constexpr double kZ1e4 = 3.890591886;  // p = 1e-4: the false-alarm rate every test here uses
constexpr double kZ1e5 = 4.417173413;  // p = 1e-5

}  // namespace pt::test
