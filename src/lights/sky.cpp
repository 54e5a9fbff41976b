#include "src/lights/sky.h"

#include <algorithm>
#include <cmath>

namespace pt {
namespace {

constexpr double kLumensPerWatt = 683.0;      // the photometric definition at 555 nm
constexpr double kSolarIlluminance = 128000;  // lx, outside the atmosphere

// Perez et al.'s distribution (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma).
struct Perez {
  double a, b, c, d, e;
  double operator()(double cosTheta, double gamma) const {
    double cosGamma = std::cos(gamma);
    return (1.0 + a * std::exp(b / cosTheta)) *
           (1.0 + c * std::exp(d * gamma) + e * cosGamma * cosGamma);
  }
};

// Preetham et al. 1999, Appendix A.2: the distribution coefficients of Y, x and y as linear
// functions of turbidity, and the zenith values as functions of turbidity and sun angle.
struct PreethamSky {
  Perez lumY, chromX, chromY;
  double zenithY, zenithX, zenithYChrom;  // zenith luminance (kcd/m^2) and chromaticity
  double thetaSun;
  vec3 sun;  // unit, towards the sun
};

PreethamSky MakePreetham(const SkyDesc& sky) {
  double t = sky.turbidity;
  PreethamSky p;
  p.sun = glm::normalize(sky.sunDirection);
  p.thetaSun = std::acos(std::clamp(double(p.sun.y), -1.0, 1.0));
  p.lumY = {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251,
            0.1206 * t - 2.5771, -0.0670 * t + 0.3703};
  p.chromX = {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125,
              -0.0641 * t - 0.8989, -0.0033 * t + 0.0452};
  p.chromY = {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102,
              -0.0441 * t - 1.6537, -0.0109 * t + 0.0529};
  double s = p.thetaSun, s2 = s * s, s3 = s2 * s, t2 = t * t;
  double chi = (4.0 / 9.0 - t / 120.0) * (M_PI - 2.0 * s);
  p.zenithY = (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
  p.zenithX = t2 * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s) +
              t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s + 0.00394) +
              (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s + 0.25886);
  p.zenithYChrom = t2 * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s) +
                   t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s + 0.00516) +
                   (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s + 0.26688);
  return p;
}

// CIE xyY -> linear Rec. 709 RGB, negatives (out of gamut) clamped.
vec3 XyYToRgb(double x, double y, double lum) {
  if (!(y > 0.0) || !(lum > 0.0)) return vec3(0.0f);
  double bigX = x * lum / y, bigZ = std::max(0.0, 1.0 - x - y) * lum / y;
  double r = 3.2404542 * bigX - 1.5371385 * lum - 0.4985314 * bigZ;
  double g = -0.9692660 * bigX + 1.8760108 * lum + 0.0415560 * bigZ;
  double b = 0.0556434 * bigX - 0.2040259 * lum + 1.0572252 * bigZ;
  return vec3(float(std::max(r, 0.0)), float(std::max(g, 0.0)), float(std::max(b, 0.0)));
}

vec3 PreethamRadiance(const PreethamSky& p, vec3 w) {
  // Directions at the horizon are clipped just above it, as Preetham's code does (1 / cos).
  double cosTheta = std::max(double(w.y), std::cos(0.5 * M_PI - 0.001));
  double gamma = std::acos(std::clamp(double(glm::dot(w, p.sun)), -1.0, 1.0));
  double cosZero = 1.0;
  auto ratio = [&](const Perez& f) { return f(cosTheta, gamma) / f(cosZero, p.thetaSun); };
  double lum = p.zenithY * ratio(p.lumY) * 1000.0 / kLumensPerWatt;  // kcd/m^2 -> W-ish
  return XyYToRgb(p.zenithX * ratio(p.chromX), p.zenithYChrom * ratio(p.chromY), lum);
}

// The map-frame direction of map position (u, v) in [0, 1]^2.
vec3 MapDirection(double u, double v) {
  double theta = M_PI * v, phi = 2.0 * M_PI * (u - 0.5);
  return vec3(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
              float(-std::sin(theta) * std::cos(phi)));
}

// Adds the sun's disk to the texels it covers: each texel near it is sampled 16 x 16 times
// uniformly in solid angle, and the shares are scaled so that the disk's solid angle is
// exactly covered, keeping the sun's power.
void AddSunDisk(const SkyDesc& sky, uint32_t w, uint32_t h, std::vector<vec3>* texels) {
  vec3 sun = glm::normalize(sky.sunDirection);
  double sinR = std::sin(kSunAngularRadius);
  vec3 radiance = SunIrradiance(sky) * float(1.0 / (M_PI * sinR * sinR));
  double cosR = std::cos(kSunAngularRadius);
  double reach = kSunAngularRadius + 2.0 * M_PI / h;  // the disk plus a texel's diagonal
  struct Share {
    size_t index;
    double inDisk, texel;  // solid angles
  };
  std::vector<Share> shares;
  double covered = 0.0;
  const int n = 16;
  for (uint32_t j = 0; j < h; ++j) {
    double t0 = M_PI * j / h, t1 = M_PI * (j + 1) / h;
    for (uint32_t i = 0; i < w; ++i) {
      vec3 centre = MapDirection((i + 0.5) / w, (j + 0.5) / h);
      double angle = std::acos(std::clamp(double(glm::dot(centre, sun)), -1.0, 1.0));
      if (angle > reach) continue;
      double texelSolidAngle = (std::cos(t0) - std::cos(t1)) * 2.0 * M_PI / w;
      int inside = 0;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          double z = std::cos(t0) + (b + 0.5) / n * (std::cos(t1) - std::cos(t0));
          double v = std::acos(z) / M_PI;
          if (glm::dot(MapDirection((i + (a + 0.5) / n) / w, v), sun) >= cosR) ++inside;
        }
      if (inside == 0) continue;
      double share = texelSolidAngle * inside / (n * n);
      shares.push_back({size_t(j) * w + i, share, texelSolidAngle});
      covered += share;
    }
  }
  double disk = 2.0 * M_PI * (1.0 - cosR);
  for (const Share& s : shares)
    (*texels)[s.index] += radiance * float(s.inDisk * (disk / covered) / s.texel);
}

}  // namespace

vec3 SunDirection(double elevationDegrees, double azimuthDegrees) {
  double e = elevationDegrees * M_PI / 180.0, a = azimuthDegrees * M_PI / 180.0;
  return vec3(float(std::cos(e) * std::sin(a)), float(std::sin(e)),
              float(-std::cos(e) * std::cos(a)));
}

vec3 SkyRadiance(const SkyDesc& sky, vec3 w) { return PreethamRadiance(MakePreetham(sky), w); }

vec3 SunIrradiance(const SkyDesc& sky) {
  vec3 sun = glm::normalize(sky.sunDirection);
  if (!(sun.y > 0.0f)) return vec3(0.0f);
  // Kasten and Young's (1989) relative air mass of the sun's zenith angle z (degrees).
  double z = std::acos(double(sun.y)) * 180.0 / M_PI;
  double airMass = 1.0 / (std::cos(z * M_PI / 180.0) + 0.50572 * std::pow(96.07995 - z, -1.6364));
  // Preetham's attenuation: Rayleigh optical depth 0.008735 lambda^-4.08 and Angstrom's
  // aerosol beta lambda^-1.3 with beta = 0.04608 T - 0.04586 (lambda in micrometres), at the
  // wavelengths that stand for red, green and blue.
  double beta = 0.04608 * sky.turbidity - 0.04586;
  const double lambda[3] = {0.610, 0.550, 0.465};
  vec3 e;
  for (int c = 0; c < 3; ++c) {
    double depth = 0.008735 * std::pow(lambda[c], -4.08) + beta * std::pow(lambda[c], -1.3);
    e[c] = float(kSolarIlluminance / kLumensPerWatt * std::exp(-airMass * depth));
  }
  return e;
}

void BakeSky(const SkyDesc& sky, bool sunInMap, uint32_t* width, uint32_t* height,
             std::vector<vec3>* texels) {
  PreethamSky p = MakePreetham(sky);
  uint32_t w = uint32_t(sky.width), h = w / 2;
  texels->assign(size_t(w) * h, vec3(0.0f));
  glm::dvec3 irradiance(0.0);  // of the sky on the horizontal plane
  for (uint32_t j = 0; j < h / 2; ++j) {  // the upper hemisphere (h is even)
    double solidAngle = (std::cos(M_PI * j / h) - std::cos(M_PI * (j + 1) / h)) * 2.0 * M_PI / w;
    for (uint32_t i = 0; i < w; ++i) {
      vec3 sum(0.0f);
      for (int s = 0; s < 4; ++s)
        sum += PreethamRadiance(p, MapDirection((i + 0.25 + 0.5 * (s & 1)) / w,
                                                (j + 0.25 + 0.5 * (s >> 1)) / h));
      vec3 texel = 0.25f * sum;
      (*texels)[size_t(j) * w + i] = texel;
      double cosTheta = std::cos(M_PI * (j + 0.5) / h);
      irradiance += glm::dvec3(texel) * (cosTheta * solidAngle);
    }
  }
  vec3 sun = glm::normalize(sky.sunDirection);
  irradiance += glm::dvec3(SunIrradiance(sky)) * double(std::max(0.0f, sun.y));
  vec3 ground = sky.groundAlbedo * vec3(irradiance / M_PI);
  for (size_t k = size_t(h / 2) * w; k < texels->size(); ++k) (*texels)[k] = ground;
  if (sunInMap) AddSunDisk(sky, w, h, texels);
  *width = w;
  *height = h;
}

DirectionalLightDesc SkySun(const SkyDesc& sky) {
  DirectionalLightDesc d;
  d.direction = glm::normalize(sky.sunDirection);
  d.irradiance = SunIrradiance(sky);
  d.angularRadius = float(kSunAngularRadius);
  d.partOfEnvironment = true;
  return d;
}

}  // namespace pt
