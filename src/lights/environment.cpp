#include "src/lights/environment.h"

#include <cmath>

#include "src/scene/transform.h"

namespace pt {
namespace {

// Solid angle of a texel of row j, in double (the host tables' precision).
double TexelSolidAngle(uint32_t j, uint32_t width, uint32_t height) {
  double halfWidth = 0.5 * M_PI / height;
  return 2.0 * std::sin(M_PI * (j + 0.5) / height) * std::sin(halfWidth) * (2.0 * M_PI / width);
}

// cdf[0] = 0, cdf[k] = sum of weights before k / total, cdf[n] = 1; uniform when all are 0
// (a row that is never chosen still needs a valid table).
void FillCdf(const double* weights, size_t n, double total, float* cdf) {
  double running = 0.0;
  cdf[0] = 0.0f;
  for (size_t k = 0; k < n; ++k) {
    running += total > 0.0 ? weights[k] : 1.0;
    cdf[k + 1] = float(running / (total > 0.0 ? total : double(n)));
  }
  cdf[n] = 1.0f;
}

}  // namespace

mat3 EnvironmentRotation(vec3 rotateDegrees) {
  return mat3(TrsMatrix(vec3(1.0f), rotateDegrees, vec3(0.0f)));
}

void BuildEnvironmentMap(Scene& scene) {
  const EnvironmentDesc& d = scene.desc.environment;
  EnvironmentView& e = scene.env;
  e = EnvironmentView{};
  e.hiddenFromCamera = d.visibleToCamera ? 0u : 1u;
  e.cameraColor = d.cameraColor;
  scene.envRowCdf.clear();
  scene.envColumnCdf.clear();
  if (!d.HasMap()) return;
  e.width = d.width;
  e.height = d.height;
  e.strength = d.strength;
  e.toWorld = EnvironmentRotation(d.rotateDegrees);
  e.toLocal = glm::transpose(e.toWorld);
  uint32_t w = d.width, h = d.height;
  scene.envRowCdf.assign(h + 1, 0.0f);
  scene.envColumnCdf.assign(size_t(h) * (w + 1), 0.0f);
  std::vector<double> rowWeight(h, 0.0), texelWeight(w);
  double total = 0.0;
  for (uint32_t j = 0; j < h; ++j) {
    double rowSum = 0.0;
    for (uint32_t i = 0; i < w; ++i) {
      texelWeight[i] = double(Luminance(d.texels[size_t(j) * w + i]));
      rowSum += texelWeight[i];
    }
    FillCdf(texelWeight.data(), w, rowSum, &scene.envColumnCdf[size_t(j) * (w + 1)]);
    rowWeight[j] = rowSum * TexelSolidAngle(j, w, h);
    total += rowWeight[j];
  }
  FillCdf(rowWeight.data(), h, total, scene.envRowCdf.data());
}

double EnvironmentMapLuminanceIntegral(const Scene& scene) {
  const EnvironmentDesc& d = scene.desc.environment;
  if (!d.HasMap()) return 0.0;
  double sum = 0.0;
  for (uint32_t j = 0; j < d.height; ++j) {
    double row = 0.0;
    for (uint32_t i = 0; i < d.width; ++i)
      row += double(Luminance(d.texels[size_t(j) * d.width + i]));
    sum += row * TexelSolidAngle(j, d.width, d.height);
  }
  return sum * double(d.strength);
}

Light MakeDirectionalLight(const DirectionalLightDesc& desc, const EnvironmentDesc& env) {
  Light light;
  light.type = LightType::kDirectional;
  vec3 direction = desc.direction;
  vec3 irradiance = desc.irradiance;
  if (desc.partOfEnvironment) {
    direction = EnvironmentRotation(env.rotateDegrees) * direction;
    irradiance *= env.strength;
  }
  light.direction = glm::normalize(direction);
  light.irradiance = irradiance;
  double r = desc.angularRadius;
  if (r > 0.0) {
    double sinHalf = std::sin(0.5 * r);
    light.oneMinusCos = float(2.0 * sinHalf * sinHalf);
    light.cosAngle = float(std::cos(r));
    // E on a facing plane = L x integral of cos over the cone = L pi sin^2(r), for r <= 90 deg.
    double sinR = std::sin(r);
    light.radiance = irradiance * float(1.0 / (M_PI * sinR * sinR));
  }
  return light;
}

}  // namespace pt
