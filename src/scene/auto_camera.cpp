#include "src/scene/auto_camera.h"

#include <algorithm>
#include <cmath>

namespace pt {

CameraDesc FrameBounds(vec3 lo, vec3 hi, float aspect, float fovYDegrees) {
  glm::dvec3 dlo(lo), dhi(hi);
  bool valid = glm::all(glm::lessThanEqual(dlo, dhi)) && std::isfinite(glm::dot(dlo, dlo)) &&
               std::isfinite(glm::dot(dhi, dhi));
  glm::dvec3 center = valid ? 0.5 * (dlo + dhi) : glm::dvec3(0.0);
  double radius = valid ? 0.5 * glm::length(dhi - dlo) : 0.0;
  if (!(radius > 0.0) || !std::isfinite(radius)) radius = 1.0;
  double halfY = glm::radians(double(fovYDegrees)) * 0.5;
  double halfX = std::atan(std::tan(halfY) * double(aspect > 0.0f ? aspect : 1.0f));
  double half = std::min(halfY, halfX);
  double distance = double(kAutoCameraMargin) * radius / std::sin(half);
  double azimuth = glm::radians(double(kAutoCameraAzimuth));
  double elevation = glm::radians(double(kAutoCameraElevation));
  glm::dvec3 toCamera(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                      std::cos(elevation) * std::cos(azimuth));
  CameraDesc camera;
  camera.position = vec3(center + distance * toCamera);
  camera.lookAt = vec3(center);
  camera.up = vec3(0.0f, 1.0f, 0.0f);
  camera.fovY = fovYDegrees;
  camera.focusDistance = float(distance);
  return camera;
}

}  // namespace pt
