#include "src/io/tone_mapping.h"

#include <algorithm>
#include <cmath>

#include "src/io/image_io.h"

namespace pt {
namespace {

// AgX's inset (Blender 4's AgX, after Troy Sobotka): each primary pulled a little towards the
// others, so a very bright saturated colour reaches white through the curve rather than
// clipping in one channel. Rows sum to 1: greys stay grey.
constexpr double kInset[3][3] = {{0.842479062253094, 0.0784335999999992, 0.0792237451477643},
                                 {0.0423282422610123, 0.878468636469772, 0.0791661274605434},
                                 {0.0423756549057051, 0.0784336, 0.879142973793104}};

// The log2 encoding: 16.5 stops, from 10 below mid grey (0.18) to 6.5 above.
constexpr double kMinStops = -10.0, kMaxStops = 6.5, kMidGrey = 0.18;
// The sigmoid through the pivot (mid grey's encoding, sRGB's encoding of mid grey) with slope
// kSlope there, rolling off as x / (1 + x^p)^(1/p) towards (0, 0) and (1, 1).
constexpr double kPivotX = -kMinStops / (kMaxStops - kMinStops);
constexpr double kPivotY = 0.46135612950044164;  // sRGB OETF of 0.18
constexpr double kSlope = 2.4, kPower = 1.5;

// The scale that makes y_pivot + scale * h(slope * dx / scale) reach y_pivot + dy at dx,
// h(u) = u / (1 + u^p)^(1/p): k / (1 + (k/s)^p)^(1/p) = dy with k = slope * dx.
double RollOffScale(double dx, double dy) {
  double k = kSlope * dx;
  return k / std::pow(std::pow(k / dy, kPower) - 1.0, 1.0 / kPower);
}

double Sigmoid(double x) {
  static const double shoulder = RollOffScale(1.0 - kPivotX, 1.0 - kPivotY);
  static const double toe = RollOffScale(kPivotX, kPivotY);
  double d = x - kPivotX, scale = d >= 0.0 ? shoulder : toe;
  double u = kSlope * std::fabs(d) / scale;
  double h = u / std::pow(1.0 + std::pow(u, kPower), 1.0 / kPower);
  return kPivotY + std::copysign(scale * h, d);
}

struct Outset {
  double m[3][3];
};

// The outset: the inset's inverse, applied to the curve's output (restores the primaries'
// directions after the curve, as AgX does).
Outset MakeOutset() {
  const auto& a = kInset;
  double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
               a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  Outset o;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      // The adjugate's (r, c) entry: the cofactor of (c, r).
      int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
      o.m[r][c] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
    }
  }
  return o;
}

uint8_t Byte(double v) { return uint8_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

}  // namespace

const char* ToneMappingName(ToneMapping mapping) {
  return mapping == ToneMapping::kAgx ? "agx" : "clip";
}

bool ParseToneMapping(const std::string& name, ToneMapping* mapping) {
  if (name == "clip") *mapping = ToneMapping::kClip;
  else if (name == "agx") *mapping = ToneMapping::kAgx;
  else return false;
  return true;
}

vec3 AgxDisplay(vec3 linear) {
  static const Outset outset = MakeOutset();
  double in[3] = {linear.x, linear.y, linear.z}, curve[3];
  for (int r = 0; r < 3; ++r) {
    double v = kInset[r][0] * in[0] + kInset[r][1] * in[1] + kInset[r][2] * in[2];
    double stops = std::log2(std::max(v, 1e-10) / kMidGrey);  // NaN-free: max picks 1e-10
    double x = std::clamp((stops - kMinStops) / (kMaxStops - kMinStops), 0.0, 1.0);
    curve[r] = Sigmoid(x);
  }
  vec3 out;
  for (int r = 0; r < 3; ++r) {
    double v = outset.m[r][0] * curve[0] + outset.m[r][1] * curve[1] + outset.m[r][2] * curve[2];
    out[r] = float(std::clamp(v, 0.0, 1.0));
  }
  return out;
}

std::vector<uint8_t> DisplayPixels(const std::vector<float>& rgb, const DisplaySettings& display) {
  float scale = std::exp2(display.exposure);
  std::vector<uint8_t> out(rgb.size());
  if (display.toneMapping == ToneMapping::kClip) {
    for (size_t i = 0; i < out.size(); ++i) out[i] = LinearToSrgb8(rgb[i] * scale);
    return out;
  }
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    vec3 v = AgxDisplay(vec3(rgb[i], rgb[i + 1], rgb[i + 2]) * scale);
    for (int c = 0; c < 3; ++c) out[i + size_t(c)] = Byte(v[c]);
  }
  return out;
}

}  // namespace pt
