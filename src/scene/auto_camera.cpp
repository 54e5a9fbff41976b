#include "src/scene/auto_camera.h"

#include <algorithm>
#include <cmath>

namespace pt {

double AutoCameraDistance(glm::dvec3 half, double tanHalfX, double tanHalfY) {
  double margin = double(kAutoCameraMargin);
  double fit = half.z + margin * std::max(half.x / tanHalfX, half.y / tanHalfY);
  return std::max(fit, margin * glm::length(half));
}

CameraDesc FrameBounds(vec3 lo, vec3 hi, float aspect, float fovYDegrees) {
  glm::dvec3 dlo(lo), dhi(hi);
  bool valid = glm::all(glm::lessThanEqual(dlo, dhi)) && std::isfinite(glm::dot(dlo, dlo)) &&
               std::isfinite(glm::dot(dhi, dhi));
  glm::dvec3 center = valid ? 0.5 * (dlo + dhi) : glm::dvec3(0.0);
  glm::dvec3 half = valid ? 0.5 * (dhi - dlo) : glm::dvec3(0.0);
  double extent = glm::length(half);
  if (!(extent > 0.0) || !std::isfinite(extent)) half = glm::dvec3(1.0);
  double tanHalfY = std::tan(glm::radians(double(fovYDegrees)) * 0.5);
  double tanHalfX = tanHalfY * double(aspect > 0.0f ? aspect : 1.0f);
  double distance = AutoCameraDistance(half, tanHalfX, tanHalfY);
  CameraDesc camera;
  camera.position = vec3(center + glm::dvec3(0.0, 0.0, distance));
  camera.lookAt = vec3(center);
  camera.up = vec3(0.0f, 1.0f, 0.0f);
  camera.fovY = fovYDegrees;
  camera.focusDistance = float(distance);
  return camera;
}

}  // namespace pt
