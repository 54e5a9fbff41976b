// The Owen-scrambled padded Sobol sampler (src/core/sobol_burley.h, RngKey::Draw4 with
// SamplerKind::kSobol) as a sequence: every power-of-two block of a pixel's samples is a
// (0,2)-net in each pair of a Draw4; values lie in [0, 1); pairs, dimension groups, bounces
// and pixels are decorrelated; one sample's values over many pixels are uniform (chi-square).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "src/core/rng.h"
#include "tests/render_test_util.h"
#include "tests/stat_test_util.h"

namespace pt::test {
namespace {

RngKey SobolKey(uint32_t pixel, uint32_t sample, uint32_t seed) {
  return RngKey{pixel, sample, seed, SamplerKind::kSobol};
}

// The two pairs of a Draw4 as the sampler stratifies them (rng.h: pair 0 is the camera
// group's (x, y) and the other groups' (y, z)).
struct DrawPairs {
  vec2 first, second;
};
DrawPairs PairsOf(vec4 u, uint32_t dim) {
  if (dim == kDimCamera) return {vec2(u.x, u.y), vec2(u.z, u.w)};
  return {vec2(u.y, u.z), vec2(u.x, u.w)};
}

// Exactly one of the n = 2^k points in each elementary interval of every shape
// 2^-a x 2^-(k-a). Floats of 24 bits times a power of two are exact, so floor() is too.
bool IsZeroTwoNet(const std::vector<vec2>& points, int k) {
  for (int a = 0; a <= k; ++a) {
    std::vector<int> cells(size_t(1) << k, 0);
    for (vec2 p : points) {
      uint32_t cx = uint32_t(std::floor(p.x * float(1u << a)));
      uint32_t cy = uint32_t(std::floor(p.y * float(1u << (k - a))));
      if (++cells[(cx << (k - a)) | cy] > 1) return false;
    }
  }
  return true;
}

TEST(SobolSequence, ReverseBitsAndTheSecondDimensionFollowTheirDefinitions) {
  for (uint32_t x : {0u, 1u, 0x80000000u, 0x12345678u, 0xdeadbeefu, 0xffffffffu}) {
    uint32_t slow = 0;
    for (int b = 0; b < 32; ++b) slow |= ((x >> b) & 1u) << (31 - b);
    EXPECT_EQ(ReverseBits32(x), slow) << x;
    // Dimension 1 from its direction numbers: v_0 = 2^31, v_j+1 = v_j ^ (v_j >> 1).
    uint32_t v = 1u << 31, sobol = 0;
    for (uint32_t i = x; i != 0; i >>= 1, v ^= v >> 1)
      if (i & 1u) sobol ^= v;
    EXPECT_EQ(SobolDimension1(x), sobol) << x;
  }
  // Unscrambled, the first two dimensions are a (0,m,2)-net for every m (a (0,2)-sequence).
  for (int k = 0; k <= 12; ++k) {
    std::vector<vec2> points;
    for (uint32_t i = 0; i < (1u << k); ++i)
      points.push_back(vec2(BitsToUnitFloat(ReverseBits32(i)),
                            BitsToUnitFloat(SobolDimension1(i))));
    EXPECT_TRUE(IsZeroTwoNet(points, k)) << "2^" << k;
  }
}

// SobolBurleyPair, its reversals cancelled, is the paper's composition: shuffle the index by
// a nested uniform scramble, take Sobol dimensions 0 and 1, scramble each.
TEST(SobolSequence, PairsAreScrambledSobolPointsOfTheShuffledIndex) {
  for (glm::uvec3 s : {glm::uvec3(0x1234567u, 0x9abcdefu, 0xdeadbeefu),
                       glm::uvec3(7u, 0u, 0xffffffffu)})
    for (uint32_t index : {0u, 1u, 2u, 3u, 100u, 65535u, 0x80000001u}) {
      glm::uvec2 got = SobolBurleyPair(index, s);
      uint32_t i = NestedUniformScramble(index, s.x);
      EXPECT_EQ(got.x, NestedUniformScramble(ReverseBits32(i), s.y)) << index;
      EXPECT_EQ(got.y, NestedUniformScramble(SobolDimension1(i), s.z)) << index;
    }
}

TEST(SobolSequence, EveryPowerOfTwoBlockIsANetInEachPair) {
  for (uint32_t pixel : {0u, 1u, 4097u, 1000003u})
    for (uint32_t seed : {0u, 7u})
      for (uint32_t bounce : {0u, 1u, 9u})
        for (uint32_t dim : {uint32_t(kDimCamera), uint32_t(kDimLight), uint32_t(kDimBsdf)}) {
          std::vector<DrawPairs> draws;
          for (uint32_t s = 0; s < 512; ++s)
            draws.push_back(PairsOf(SobolKey(pixel, s, seed).Draw4(bounce, dim), dim));
          for (int k = 0; k <= 8; ++k) {
            // The prefix, and the block after it (a resumed or continued film's samples).
            for (uint32_t start : {0u, 1u << k}) {
              std::vector<vec2> first, second;
              for (uint32_t s = start; s < start + (1u << k); ++s) {
                first.push_back(draws[s].first);
                second.push_back(draws[s].second);
              }
              SCOPED_TRACE(::testing::Message() << "pixel " << pixel << " seed " << seed
                                                << " bounce " << bounce << " dim " << dim
                                                << " samples [" << start << ", "
                                                << start + (1u << k) << ")");
              EXPECT_TRUE(IsZeroTwoNet(first, k));
              EXPECT_TRUE(IsZeroTwoNet(second, k));
            }
          }
          for (const DrawPairs& d : draws)
            for (float v : {d.first.x, d.first.y, d.second.x, d.second.y}) {
              EXPECT_GE(v, 0.0f);
              EXPECT_LT(v, 1.0f);
            }
        }
}

TEST(SobolSequence, ValuesReachBothEndsOfTheUnitIntervalButNeverOne) {
  EXPECT_EQ(BitsToUnitFloat(0u), 0.0f);
  EXPECT_LT(BitsToUnitFloat(0xffffffffu), 1.0f);
  // A net of 2^12 points has one in [0, 2^-12) and one in [1 - 2^-12, 1) on each axis.
  const uint32_t n = 1u << 12;
  float lo = 1.0f, hi = 0.0f;
  for (uint32_t s = 0; s < n; ++s) {
    vec4 u = SobolKey(77u, s, 3u).Draw4(2, kDimBsdf);
    lo = std::fmin(lo, u.y);
    hi = std::fmax(hi, u.y);
  }
  EXPECT_LT(lo, 1.0f / n);
  EXPECT_GE(hi, 1.0f - 1.0f / n);
  EXPECT_LT(hi, 1.0f);
}

// Pearson correlation of two sequences.
double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= a.size(), mb /= b.size();
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Independent streams have correlation ~ N(0, 1/n). The samples of one stream are a
// scrambled net, whose estimates of a mean have at most e times Monte Carlo's variance for a
// base-2 (0,m,2)-net (Owen 1997): the bound widens by sqrt(e). The comparisons share a
// false-alarm budget of 1e-6 under that worst case.
TEST(SobolSequence, PairsGroupsBouncesAndPixelsAreDecorrelated) {
  const int n = 4096;
  struct Stream {
    uint32_t pixel, bounce, dim;
    int coordinate;  // 0..3 of Draw4
  };
  const Stream base{123u, 1u, kDimBsdf, 1};
  const std::vector<Stream> others = {
      {123u, 1u, kDimBsdf, 0},  {123u, 1u, kDimBsdf, 3},  // the other pair
      {123u, 1u, kDimBsdf, 2},                             // the same pair's other axis
      {123u, 1u, kDimLight, 1}, {123u, 2u, kDimBsdf, 1},  // group, bounce
      {124u, 1u, kDimBsdf, 1},  {123u + 640u, 1u, kDimBsdf, 1}};  // neighbouring pixels
  auto values = [&](const Stream& s) {
    std::vector<double> v;
    for (uint32_t i = 0; i < uint32_t(n); ++i)
      v.push_back(SobolKey(s.pixel, i, 5u).Draw4(s.bounce, s.dim)[s.coordinate]);
    return v;
  };
  const std::vector<double> x = values(base);
  const double bound =
      TwoSidedNormalQuantile(1e-6 / others.size()) * std::sqrt(std::exp(1.0) / n);
  for (const Stream& s : others) {
    double r = Correlation(x, values(s));
    EXPECT_LT(std::fabs(r), bound) << "pixel " << s.pixel << " bounce " << s.bounce << " dim "
                                   << s.dim << " coordinate " << s.coordinate << ": r = " << r;
  }
}

// With two half films (--denoise) the even and the odd samples are two replicates (rng.h,
// kSobolHalves): each half's power-of-two blocks are nets of their own, and the two halves are
// scrambled independently (decorrelated; not the one sequence's even and odd points).
TEST(SobolSequence, TheHalvesOfADenoisedFilmAreTwoIndependentNets) {
  for (uint32_t pixel : {0u, 4097u})
    for (uint32_t dim : {uint32_t(kDimCamera), uint32_t(kDimBsdf)}) {
      std::vector<vec2> half[2];
      for (uint32_t s = 0; s < 512; ++s)
        half[s & 1u].push_back(
            PairsOf(RngKey{pixel, s, 3u, SamplerKind::kSobolHalves}.Draw4(1, dim), dim).first);
      for (int h = 0; h < 2; ++h)
        for (int k = 0; k <= 8; ++k) {
          std::vector<vec2> block(half[h].begin(), half[h].begin() + (1u << k));
          EXPECT_TRUE(IsZeroTwoNet(block, k)) << "pixel " << pixel << " dim " << dim << " half "
                                             << h << ", 2^" << k;
        }
      // Not the one sequence's halves: sample 0 of each half is that sequence's first point
      // scrambled another way.
      EXPECT_NE(half[0][0], PairsOf(SobolKey(pixel, 0u, 3u).Draw4(1, dim), dim).first);
    }
  const int n = 4096;
  std::vector<double> even, odd;
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    even.push_back(RngKey{9u, 2 * i, 5u, SamplerKind::kSobolHalves}.Draw4(0, kDimCamera).x);
    odd.push_back(RngKey{9u, 2 * i + 1, 5u, SamplerKind::kSobolHalves}.Draw4(0, kDimCamera).x);
  }
  double bound = TwoSidedNormalQuantile(1e-6) * std::sqrt(std::exp(1.0) / n);
  EXPECT_LT(std::fabs(Correlation(even, odd)), bound);
}

// One sample index over many pixels: the scrambles make each value uniform on its own. A
// chi-square over 64 bins of each coordinate and over 16 x 16 bins of each pair, for a few
// sample indices; the tests share a false-alarm budget of 1e-5.
TEST(SobolSequence, OneSampleOverManyPixelsIsUniform) {
  const uint32_t pixels = 1u << 15;
  const std::vector<uint32_t> samples = {0u, 1u, 37u};
  const int tests = int(samples.size()) * 6;
  for (uint32_t s : samples) {
    std::vector<double> bins1[4], bins2[2];
    for (auto& b : bins1) b.assign(64, 0.0);
    for (auto& b : bins2) b.assign(256, 0.0);
    for (uint32_t p = 0; p < pixels; ++p) {
      vec4 u = SobolKey(p, s, 11u).Draw4(0, kDimCamera);
      for (int c = 0; c < 4; ++c) bins1[c][int(u[c] * 64.0f)] += 1.0;
      bins2[0][int(u.x * 16.0f) * 16 + int(u.y * 16.0f)] += 1.0;
      bins2[1][int(u.z * 16.0f) * 16 + int(u.w * 16.0f)] += 1.0;
    }
    auto expectUniform = [&](const std::vector<double>& observed, const char* what) {
      double expected = double(pixels) / observed.size(), chi2 = 0.0;
      for (double o : observed) chi2 += (o - expected) * (o - expected) / expected;
      double p = ChiSquarePValue(chi2, int(observed.size()) - 1);
      EXPECT_GT(p, 1e-5 / tests) << what << " of sample " << s << ": chi2 " << chi2;
    };
    for (int c = 0; c < 4; ++c) expectUniform(bins1[c], "a coordinate");
    for (int q = 0; q < 2; ++q) expectUniform(bins2[q], "a pair");
  }
}

TEST(SobolSequence, IndependentIsTheDefaultAndUnchanged) {
  RngKey key{9u, 4u, 2u};
  EXPECT_EQ(key.sampler, SamplerKind::kIndependent);
  glm::uvec4 h = Pcg4d(glm::uvec4(9u, 4u, 1u * kDimsPerBounce + kDimLight, 2u));
  vec4 u = key.Draw4(1, kDimLight);
  EXPECT_EQ(u.x, BitsToUnitFloat(h.x));
  EXPECT_EQ(u.w, BitsToUnitFloat(h.w));
  EXPECT_NE(SobolKey(9u, 4u, 2u).Draw4(1, kDimLight).x, u.x);
}

}  // namespace
}  // namespace pt::test
