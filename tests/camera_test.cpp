// The camera conventions of the scene format: pixel (0,0) top-left, fov_y vertical whatever
// the aspect, and the thin lens focusing every lens position onto the focus plane.
#include <gtest/gtest.h>

#include "src/integrator/stages/generate.h"
#include "src/scene/scene.h"

namespace pt {
namespace {

TEST(Camera, TopLeftPixelAndVerticalFov) {
  CameraDesc d;
  d.position = vec3(0, 0, 0);
  d.lookAt = vec3(0, 0, -1);
  d.fovY = 90.0f;
  Camera cam = MakeCamera(d, 200, 100);
  // The top edge's centre looks up at 45 degrees: fov_y is the vertical angle.
  Ray top = CameraRay(cam, 100.0f, 0.0f, 200.0f, 100.0f, vec2(0.5f));
  EXPECT_NEAR(top.d.y, std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(top.d.x, 0.0f, 1e-6f);
  // Pixel (0, 0) is the top-left corner: up and to the left (-x with this camera).
  Ray corner = CameraRay(cam, 0.0f, 0.0f, 200.0f, 100.0f, vec2(0.5f));
  EXPECT_LT(corner.d.x, 0.0f);
  EXPECT_GT(corner.d.y, 0.0f);
  // The horizontal extent follows the aspect: tan(half width) = 2 tan(45 deg).
  Ray right = CameraRay(cam, 200.0f, 50.0f, 200.0f, 100.0f, vec2(0.5f));
  EXPECT_NEAR(right.d.x / -right.d.z, 2.0f, 1e-5f);
}

TEST(Camera, ThinLensFocusesEveryLensPointOnTheFocusPlane) {
  CameraDesc d;
  d.position = vec3(0, 1, 5);
  d.lookAt = vec3(0, 1, 0);
  d.fovY = 40.0f;
  d.apertureRadius = 0.3f;
  d.focusDistance = 3.0f;
  Camera cam = MakeCamera(d, 64, 64);
  for (float px : {3.5f, 31.0f, 60.25f}) {
    vec3 focus(0.0f);
    for (int k = 0; k < 16; ++k) {
      vec2 lens((k % 4 + 0.5f) / 4.0f, (k / 4 + 0.5f) / 4.0f);
      Ray r = CameraRay(cam, px, 20.0f, 64.0f, 64.0f, lens);
      // Where the ray meets the plane 3 units in front of the camera (z = 2).
      vec3 p = r.o + r.d * ((r.o.z - 2.0f) / -r.d.z);
      if (k == 0) focus = p;
      EXPECT_NEAR(glm::length(p - focus), 0.0f, 1e-5f) << "pixel " << px << " lens " << k;
      if (k == 15) {
        EXPECT_GT(glm::length(r.o - cam.position), 0.05f);  // the lens is open
      }
    }
  }
}

}  // namespace
}  // namespace pt
