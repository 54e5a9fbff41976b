// The built-in denoiser (src/denoise/) on the CPU: what it must leave alone (a constant image,
// a noise-free one, an albedo edge), what it must never do (NaN or Inf out, depend on the
// thread count), and that it does denoise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "src/denoise/denoiser.h"
#include "tests/denoise_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

std::vector<float> DenoiseOnCpu(FilmImage img, int threads = 2, DenoiseSettings s = {}) {
  MakeCpuDenoiser(threads, s)->Denoise(img);
  return img.denoised;
}

float MaxAbsDifference(const std::vector<float>& a, const std::vector<float>& b) {
  float m = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

// Every value the same: averaging gives it back exactly (the sums hold differences from the
// pixel's own value), whatever the weights; variance estimates and features vary the weights.
TEST(Denoise, ConstantImageStaysConstant) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  FilmImage img = SyntheticImage(40, 30, 16, [&](int, int) {
    SyntheticPixel p;
    p.color = vec3(0.3f, 0.5f, 0.7f);
    p.albedo = vec3(u(rng), u(rng), u(rng));
    p.depth = 1.0f + 5.0f * u(rng);
    return p;
  });
  for (float& v : img.variance) v = 0.01f + u(rng);  // noisy variance estimates of no noise
  std::vector<float> out = DenoiseOnCpu(img);
  ASSERT_EQ(out.size(), img.rgb.size());
  for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], img.rgb[i]) << i;
}

// No noise (zero variance, equal halves): every colour difference is significant, so no pixel
// takes a different neighbour's value, and the image is unchanged (< 1e-4).
TEST(Denoise, NoiseFreeImageChangesLessThan1e4) {
  FilmImage img = SyntheticImage(48, 40, 64, [](int x, int y) {
    SyntheticPixel p;
    float ramp = 0.02f * float(x) + 0.01f * float(y);                   // smooth shading
    float checker = ((x / 5 + y / 7) % 2) ? 0.8f : 0.1f;                 // texture edges
    p.color = vec3(ramp * checker, 0.5f * checker, x > 30 ? 4.0f : 0.2f);  // and a bright step
    p.albedo = vec3(checker);
    return p;
  });
  std::vector<float> out = DenoiseOnCpu(img);
  EXPECT_LT(MaxAbsDifference(out, img.rgb), 1e-4f);
}

// The emission the camera saw (FilmImage::emission) stays out of the filter: an emissive
// texture of random texels in [0, 4] (in no feature: the albedo is even) over a noisy constant
// reflection (0.3, sigma 1). Filtering the whole image, a pixel finds few neighbours of its
// colour; filtering the reflection alone (DenoiseSettings::keepSeenEmission), it averages the
// window and adds its texel back.
TEST(Denoise, SeenEmissionStaysOutOfTheFilter) {
  constexpr int kSize = 64;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 4.0f);
  std::vector<float> texel(size_t(kSize) * kSize);
  for (float& t : texel) t = u(rng);
  FilmImage whole = SyntheticImage(kSize, kSize, 16, [&](int x, int y) {
    SyntheticPixel p;
    p.color = vec3(0.3f + texel[size_t(y) * kSize + size_t(x)]);
    p.sigma = 1.0f;
    return p;
  }, 5);
  FilmImage split = whole;
  split.emission.resize(whole.rgb.size());
  for (size_t i = 0; i < split.emission.size(); ++i) split.emission[i] = texel[i / 3];
  split.evenEmission = split.emission;
  split.residualVariance = whole.variance;
  auto error = [&](const std::vector<float>& image) {
    double e = 0.0;
    for (size_t i = 0; i < image.size(); ++i) e += std::pow(image[i] - 0.3 - texel[i / 3], 2.0);
    return e;
  };
  DenoiseSettings keep;
  keep.keepSeenEmission = true;
  std::vector<float> wholeOut = DenoiseOnCpu(whole, 2, keep), splitOut = DenoiseOnCpu(split, 2, keep);
  double raw = error(whole.rgb), wholeError = error(wholeOut), splitError = error(splitOut);
  EXPECT_LT(splitError, raw / 10.0) << "raw " << raw;
  EXPECT_LT(splitError, wholeError / 3.0) << "filtering the whole image " << wholeError;
  // Without the setting the planes are not read: the whole image is filtered.
  EXPECT_TRUE(BitIdentical(DenoiseOnCpu(split), wholeOut));
}

// A step in albedo (0.4 | 0.6) under even light, with noise too strong for the colour alone
// to see it (without the albedo feature the step keeps 17% of its contrast): the albedo
// feature keeps the neighbours across the edge out, so the step between the two columns at
// the edge keeps at least 95% of its contrast, while the noise on either side drops.
TEST(Denoise, AlbedoEdgeStaysSharp) {
  constexpr int kEdge = 32;
  auto at = [](int x, int) {
    SyntheticPixel p;
    float a = x < kEdge ? 0.4f : 0.6f;
    p.albedo = vec3(a);
    p.color = vec3(a);
    p.sigma = 1.0f;
    return p;
  };
  FilmImage img = SyntheticImage(64, 64, 16, at, 7);
  std::vector<float> out = DenoiseOnCpu(img);
  double left = 0.0, right = 0.0, noiseIn = 0.0, noiseOut = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int c = 0; c < 3; ++c) {
      left += out[3 * (size_t(y) * 64 + kEdge - 1) + c];
      right += out[3 * (size_t(y) * 64 + kEdge) + c];
      size_t flat = 3 * (size_t(y) * 64 + 10) + c;  // far from the edge
      noiseIn += std::pow(img.rgb[flat] - 0.4, 2.0);
      noiseOut += std::pow(out[flat] - 0.4, 2.0);
    }
  }
  double contrast = (right - left) / (64 * 3);
  EXPECT_GE(contrast, 0.95 * 0.2) << "left " << left / 192 << ", right " << right / 192;
  EXPECT_LT(noiseOut, noiseIn / 4.0);  // and it does denoise
}

// Degenerate films: black with no variance, no samples at all, one sample per pixel (no odd
// half), zero features (the background), huge and tiny values: always finite.
TEST(Denoise, NoNanOrInfForAnyInput) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<FilmImage> films;
  films.push_back(SyntheticImage(17, 9, 4, [](int, int) {
    SyntheticPixel p;
    p.color = p.albedo = p.normal = vec3(0.0f);
    p.depth = 0.0f;
    return p;
  }));
  FilmImage empty = films.back();
  for (uint32_t& n : empty.samples) n = 0;
  for (uint32_t& n : empty.evenSamples) n = 0;
  films.push_back(empty);
  films.push_back(SyntheticImage(23, 19, 1, [&](int x, int) {
    SyntheticPixel p;
    p.color = vec3(u(rng) * 100.0f);
    p.depth = x % 3 == 0 ? 0.0f : u(rng) * 1e-30f;  // the background and near-zero depths
    return p;
  }));
  films.push_back(SyntheticImage(31, 12, 8, [&](int x, int y) {
    SyntheticPixel p;
    float big = (x + y) % 2 ? 1e30f : 1e-30f;
    p.color = vec3(big * u(rng), 0.0f, big);
    p.albedo = vec3(big);
    p.normal = vec3(-big, big, 0.0f);
    p.depth = (x % 4) ? 1e30f : 1e-30f;
    p.sigma = y % 3 ? big : 0.0f;
    return p;
  }));
  // Black in both halves but with variance (a pixel's other samples were negative or the
  // odd half's mean rounded to 0): no outlier scale of 0 / 0.
  films.push_back(SyntheticImage(19, 13, 4, [&](int x, int) {
    SyntheticPixel p;
    p.color = vec3(x % 4 == 0 ? 50.0f : 0.0f);
    return p;
  }));
  for (float& v : films.back().variance) v = 1.0f + 100.0f * u(rng);
  for (FilmImage& img : films) {
    for (size_t i = 0; i < img.variance.size(); i += 7) img.variance[i] = 0.0f;
    std::vector<float> out = DenoiseOnCpu(img);
    ASSERT_EQ(out.size(), img.rgb.size());
    for (float v : out) ASSERT_TRUE(std::isfinite(v)) << img.width << "x" << img.height;
  }
}

// The same image bit for bit, run after run and whatever the thread count (every pixel's
// arithmetic is its own) and the search radius's band split.
TEST(Denoise, DeterministicAcrossRunsAndThreads) {
  FilmImage img = SyntheticImage(70, 45, 16, [](int x, int y) {
    SyntheticPixel p;
    p.color = vec3(0.1f * float(x % 9), 0.5f, float(y % 5));
    p.albedo = vec3(x < 35 ? 0.3f : 0.7f);
    p.sigma = 0.3f;
    return p;
  });
  std::vector<float> one = DenoiseOnCpu(img, 1);
  EXPECT_TRUE(BitIdentical(one, DenoiseOnCpu(img, 1)));
  EXPECT_TRUE(BitIdentical(one, DenoiseOnCpu(img, 2)));
  EXPECT_TRUE(BitIdentical(one, DenoiseOnCpu(img, 5)));
}

// The CPU's loop order and vector code change nothing: tiles of any shape (each tile computes
// the distances its patches reach past its edge anew, each task into planes of its own) and
// the x86-64-v3 and AVX-512 code and groups of 8 or of a whole window row give the image bit for
// bit, for every patch size and windows whose last group of offsets is full or not.
TEST(Denoise, SameImageForAnyTilingAndVectorCode) {
  FilmImage img = SyntheticImage(150, 37, 8, [](int x, int y) {
    SyntheticPixel p;
    p.color = vec3(0.1f * float(x % 11), 0.4f + 0.01f * float(y), float((x + y) % 3));
    p.albedo = vec3(x < 60 ? 0.2f : 0.8f, 0.5f, y < 20 ? 0.3f : 0.6f);
    p.depth = 2.0f + 0.05f * float(x % 17);
    p.sigma = 0.4f;
    return p;
  });
  const CpuDenoiseOptions options[] = {
      {32, 128, true},        {32, 128, false},        {1, 8, true}, {7, 16, false},
      {5, 1000, true},        {32, 128, true, false}};
  for (int patch = 0; patch <= 3; ++patch) {
    DenoiseSettings s;
    s.patchRadius = patch;
    s.radius = patch == 2 ? 4 : 7;  // 9 or 15 offsets a row: a group of 1 or of 7 last
    auto run = [&](const CpuDenoiseOptions& o, int threads) {
      FilmImage copy = img;
      MakeCpuDenoiserWith(threads, s, o)->Denoise(copy);
      return copy.denoised;
    };
    std::vector<float> whole = run({0, 0, false}, 1);
    for (const CpuDenoiseOptions& o : options) {
      EXPECT_TRUE(BitIdentical(whole, run(o, 3)))
          << "patch " << patch << ", tiles " << o.tileRows << "x" << o.tileColumns
          << (o.avx512 ? ", AVX-512 if here" : ", x86-64-v3")
          << (o.wideGroups ? "" : ", groups of 8");
    }
  }
  if (!CpuDenoiserHasAvx512()) std::printf("(no AVX-512 on this host: its code did not run)\n");
}

// Noise is what it removes: on a smooth image with noise the error to the truth drops by far
// more than half (the search window holds 225 pixels).
TEST(Denoise, ReducesNoiseOnASmoothImage) {
  auto truth = [](int x, int y) { return vec3(0.2f + 0.01f * float(x), 0.5f, 0.3f + 0.005f * float(y)); };
  FilmImage img = SyntheticImage(60, 50, 16, [&](int x, int y) {
    SyntheticPixel p;
    p.color = truth(x, y);
    p.sigma = 0.4f;
    return p;
  }, 5);
  std::vector<float> out = DenoiseOnCpu(img);
  double before = 0.0, after = 0.0;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 60; ++x)
      for (int c = 0; c < 3; ++c) {
        size_t i = 3 * (size_t(y) * 60 + x) + c;
        before += std::pow(img.rgb[i] - truth(x, y)[c], 2.0);
        after += std::pow(out[i] - truth(x, y)[c], 2.0);
      }
  EXPECT_LT(after, before / 8.0);
}

// A film whose halves differ far less than its sample variance says (stratified samples:
// --sampler sobol) and whose colour has detail the features do not see (a one-pixel checker):
// with the variance calibrated to the halves (nlm_variance.h) the detail stays and the error
// drops below the raw film's; with the sample variance as it is the filter takes the detail
// for noise and averages it away.
TEST(Denoise, CalibratedVarianceKeepsDetailOfAStratifiedFilm) {
  auto truth = [](int x, int y) { return vec3(((x + y) % 2 == 0) ? 0.45f : 0.55f); };
  FilmImage img = SyntheticImage(48, 40, 16, [&](int x, int y) {
    SyntheticPixel p;
    p.color = truth(x, y);
    p.sigma = 0.02f;  // the halves' real noise per sample
    return p;
  }, 9);
  for (float& v : img.variance) v = 0.4f * 0.4f;  // what the film's sample variance claims
  auto error = [&](const std::vector<float>& image) {
    double sum = 0.0;
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 48; ++x)
        for (int c = 0; c < 3; ++c)
          sum += std::pow(image[3 * (size_t(y) * 48 + x) + c] - truth(x, y)[c], 2.0);
    return sum;
  };
  DenoiseSettings calibrated, sample;
  calibrated.calibrateVariance = true;
  sample.calibrateVariance = false;
  double raw = error(img.rgb);
  double withCalibration = error(DenoiseOnCpu(img, 2, calibrated));
  double withSampleVariance = error(DenoiseOnCpu(img, 2, sample));
  EXPECT_LT(withCalibration, raw);
  EXPECT_GT(withSampleVariance, 20.0 * raw);
}

// A firefly (one sample 2,000 times the image's level) in a smooth noisy image: scaled down to
// its neighbourhood before filtering (nlm_outliers.h), so its energy reaches no neighbour;
// without the outlier passes the filter spreads it over the pixels that accept it.
TEST(Denoise, FireflyIsNotSpread) {
  FilmImage img = SyntheticImage(41, 31, 16, [](int, int) {
    SyntheticPixel p;
    p.sigma = 0.2f;
    return p;
  }, 7);
  AddFirefly(img, 20, 15, 1000.0f);
  auto worst = [&](const std::vector<float>& out) {
    float m = 0.0f;
    for (float v : out) m = std::max(m, std::fabs(v - 0.5f));
    return m;
  };
  float with = worst(DenoiseOnCpu(img));
  DenoiseSettings off;
  off.outliers = false;
  float without = worst(DenoiseOnCpu(img, 2, off));
  // The firefly adds 59 to its pixel's mean: spread, it lifts its neighbours by 0.3 (0.34
  // measured); scaled down, what is left is the noise's own (0.07 measured).
  EXPECT_LT(with, 0.15f) << without;
  EXPECT_GT(without, 0.25f) << with;
}

// A bright spot whose variance says it is real (its reference level lies far outside 3
// standard deviations) is a highlight, not an outlier: it keeps its value.
TEST(Denoise, LowNoiseHighlightKeepsItsValue) {
  FilmImage img = SyntheticImage(41, 31, 16, [](int x, int y) {
    SyntheticPixel p;
    bool spot = x >= 20 && x <= 21 && y >= 15 && y <= 16;
    p.color = vec3(spot ? 20.0f : 0.5f);
    p.sigma = spot ? 0.5f : 0.2f;
    return p;
  }, 8);
  std::vector<float> out = DenoiseOnCpu(img);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 * (15 * 41 + 20) + c], 20.0f, 1.0f);
}

TEST(Denoise, RefusesAnImageWithoutHalvesOrFeaturesAndBadSettings) {
  FilmImage img = SyntheticImage(8, 8, 4, [](int, int) { return SyntheticPixel{}; });
  FilmImage noHalves = img;
  noHalves.evenRgb.clear();
  EXPECT_NE(DenoiseInputProblem(noHalves).find("half buffers"), std::string::npos);
  EXPECT_THROW(DenoiseOnCpu(noHalves), std::invalid_argument);
  FilmImage noFeatures = img;
  noFeatures.normal.clear();
  EXPECT_THROW(DenoiseOnCpu(noFeatures), std::invalid_argument);
  FilmImage partEmission = img;  // the emission planes come all three or none
  partEmission.emission = partEmission.rgb;
  EXPECT_NE(DenoiseInputProblem(partEmission).find("emission"), std::string::npos);
  EXPECT_THROW(DenoiseOnCpu(partEmission), std::invalid_argument);
  DenoiseSettings bad;
  bad.radius = 0;
  EXPECT_THROW(DenoiseOnCpu(img, 2, bad), std::invalid_argument);
  EXPECT_EQ(DenoiseInputProblem(img), "");
}

}  // namespace
}  // namespace pt::test
