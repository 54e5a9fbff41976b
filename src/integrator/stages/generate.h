// Stage 1, generate: one camera ray per path slot (pinhole or thin lens), jittered uniformly
// inside its pixel (a one-pixel box filter).
#pragma once

#include "src/core/ray.h"
#include "src/core/sampling.h"
#include "src/integrator/path_state.h"
#include "src/integrator/wave.h"
#include "src/scene/scene_types.h"

namespace pt {

// The primary ray through image position (x, y) in pixels, with lens sample uLens.
PT_HDI Ray CameraRay(const Camera& cam, float x, float y, float width, float height, vec2 uLens) {
  float sx = (2.0f * x / width - 1.0f) * cam.tanHalfFovY * cam.aspect;
  float sy = (1.0f - 2.0f * y / height) * cam.tanHalfFovY;  // pixel row 0 is the top
  vec3 dir = glm::normalize(cam.forward + sx * cam.right + sy * cam.up);
  if (cam.apertureRadius <= 0.0f) return Ray{cam.position, dir};
  // Thin lens: every ray through the lens meets the pinhole ray on the focus plane.
  vec3 pFocus = cam.position + dir * (cam.focusDistance / glm::dot(dir, cam.forward));
  vec2 lens = cam.apertureRadius * SampleUniformDiskConcentric(uLens);
  vec3 origin = cam.position + lens.x * cam.right + lens.y * cam.up;
  return Ray{origin, glm::normalize(pFocus - origin)};
}

PT_HDI void GenerateCameraPath(const Camera& cam, const WaveInfo& wave, PathState ps,
                               uint32_t id) {
  uint32_t pixel = wave.CropPixelOf(id);
  vec4 u = wave.KeyOf(id).Draw4(0, kDimCamera);
  float x = float(wave.ImageX(pixel)) + u.x;
  float y = float(wave.ImageY(pixel)) + u.y;
  Ray ray = CameraRay(cam, x, y, float(wave.imageWidth), float(wave.imageHeight), vec2(u.z, u.w));
  ps.rayOrigin[id] = ray.o;
  ps.rayDir[id] = ray.d;
  // Throughput (1) and radiance (0) are not written: shade knows them at depth 0 (PathVertexOf)
  // and writes both there, whatever happens to the path.
  ps.prevPdf[id] = 0.0f;
  ps.flags[id] = kFlagAlive | kFlagSpecular;  // depth 0; emitters seen directly count fully
}

}  // namespace pt
