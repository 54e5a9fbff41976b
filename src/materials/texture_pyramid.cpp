#include "src/materials/texture_pyramid.h"

#include <algorithm>
#include <cmath>

#include "src/materials/srgb_table.h"

namespace pt {

double SrgbToLinear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

double LinearToSrgb(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

float Srgb8ToLinear(uint8_t code) { return SrgbCodeToLinear(code); }

namespace {

// Source texels [first, first + count) that destination texel i of n covers out of size, with
// the covered fraction of each (the weights sum to 1).
struct Footprint {
  int first, count;
  double weight[3];
};

Footprint Cover(int i, int n, int size) {
  double lo = double(i) * size / n, hi = double(i + 1) * size / n;
  Footprint f{int(lo), 0, {0, 0, 0}};
  for (int s = f.first; s < size && s < hi && f.count < 3; ++s) {
    double overlap = std::min(hi, double(s + 1)) - std::max(lo, double(s));
    f.weight[f.count++] = overlap / (hi - lo);
  }
  return f;
}

// One level down: (w, h) -> (max(1, w / 2), max(1, h / 2)), in linear RGBA doubles.
std::vector<double> Downsample(const std::vector<double>& src, int w, int h, int nw, int nh) {
  std::vector<double> dst(size_t(nw) * nh * 4, 0.0);
  for (int y = 0; y < nh; ++y) {
    Footprint fy = Cover(y, nh, h);
    for (int x = 0; x < nw; ++x) {
      Footprint fx = Cover(x, nw, w);
      double* out = &dst[(size_t(y) * nw + x) * 4];
      for (int j = 0; j < fy.count; ++j)
        for (int i = 0; i < fx.count; ++i) {
          const double* in = &src[(size_t(fy.first + j) * w + fx.first + i) * 4];
          double wgt = fy.weight[j] * fx.weight[i];
          for (int c = 0; c < 4; ++c) out[c] += wgt * in[c];
        }
    }
  }
  return dst;
}

uint32_t Encode(const double* rgba, bool srgb) {
  uint32_t code[4];
  for (int c = 0; c < 4; ++c) {
    double v = std::clamp(rgba[c], 0.0, 1.0);
    if (srgb && c < 3) v = LinearToSrgb(v);
    code[c] = uint32_t(std::lround(v * 255.0));
  }
  return PackRgba8(code[0], code[1], code[2], code[3]);
}

}  // namespace

std::vector<uint32_t> BuildTexturePyramid(uint32_t width, uint32_t height,
                                          const std::vector<uint32_t>& level0, bool srgb,
                                          uint32_t* levels) {
  std::vector<uint32_t> out(level0);
  std::vector<double> linear(level0.size() * 4);
  for (size_t i = 0; i < level0.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      uint32_t code = (level0[i] >> (8 * c)) & 0xffu;
      linear[i * 4 + c] = srgb && c < 3 ? double(Srgb8ToLinear(uint8_t(code))) : code / 255.0;
    }
  int w = int(width), h = int(height);
  uint32_t n = 1;
  while (w > 1 || h > 1) {
    int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    linear = Downsample(linear, w, h, nw, nh);
    for (size_t i = 0; i < size_t(nw) * nh; ++i) out.push_back(Encode(&linear[i * 4], srgb));
    w = nw, h = nh;
    ++n;
  }
  if (levels) *levels = n;
  return out;
}

}  // namespace pt
