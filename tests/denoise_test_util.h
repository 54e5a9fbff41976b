// Synthetic film images for the denoiser's tests: a known image, its two half films drawn
// with Gaussian noise of a known per-sample deviation, and features, as FilmImage holds them.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>

#include "src/integrator/render_api.h"

namespace pt::test {

struct SyntheticPixel {
  vec3 color{0.5f};       // the noise-free value
  vec3 albedo{0.5f};
  vec3 normal{0.0f, 0.0f, 1.0f};
  float depth = 5.0f;
  float sigma = 0.0f;     // per-sample noise deviation
};

// spp samples per pixel, the even ones (ceil(spp / 2)) in the first half film. The variance
// channel is the per-sample variance sigma^2 (what the film's Welford variance estimates).
inline FilmImage SyntheticImage(int width, int height, uint32_t spp,
                                const std::function<SyntheticPixel(int, int)>& at,
                                uint32_t seed = 1) {
  FilmImage img;
  img.width = width;
  img.height = height;
  size_t n = size_t(width) * height;
  for (auto* v : {&img.rgb, &img.variance, &img.evenRgb, &img.albedo, &img.normal})
    v->assign(3 * n, 0.0f);
  img.depth.assign(n, 0.0f);
  img.samples.assign(n, spp);
  uint32_t even = (spp + 1) / 2, odd = spp - even;
  img.evenSamples.assign(n, even);
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      SyntheticPixel p = at(x, y);
      size_t i = size_t(y) * width + x;
      for (int c = 0; c < 3; ++c) {
        float a = p.color[c] + p.sigma / std::sqrt(float(std::max(even, 1u))) * gauss(rng);
        float b = odd ? p.color[c] + p.sigma / std::sqrt(float(odd)) * gauss(rng) : a;
        img.evenRgb[3 * i + c] = a;
        img.rgb[3 * i + c] = (float(even) * a + float(odd) * b) / float(spp);
        img.variance[3 * i + c] = p.sigma * p.sigma;
        img.albedo[3 * i + c] = p.albedo[c];
        img.normal[3 * i + c] = p.normal[c];
      }
      img.depth[i] = p.depth;
    }
  }
  return img;
}

// One extra sample of `value` (a firefly: a rare bright path) in pixel (x, y)'s even half,
// the pixel's mean and variance updated as the film's running estimates would be.
inline void AddFirefly(FilmImage& img, int x, int y, float value) {
  size_t i = size_t(y) * size_t(img.width) + size_t(x);
  uint32_t n = img.samples[i], even = img.evenSamples[i];
  for (int c = 0; c < 3; ++c) {
    float& mean = img.rgb[3 * i + c];
    float& evenMean = img.evenRgb[3 * i + c];
    float oldMean = mean;
    mean = (float(n) * mean + value) / float(n + 1);
    evenMean = (float(even) * evenMean + value) / float(even + 1);
    // Welford's update of the (population) variance with the new sample.
    float& var = img.variance[3 * i + c];
    var = (float(n) * var + (value - oldMean) * (value - mean)) / float(n + 1);
  }
  img.samples[i] = n + 1;
  img.evenSamples[i] = even + 1;
}

}  // namespace pt::test
