// Scenes whose radiance is known in closed form (after pbrt-v4's integrators_test.cpp).
#include <gtest/gtest.h>

#include "tests/render_test_util.h"

namespace pt::test {
namespace {

// A diffuse sphere of albedo r in a uniform environment L: every reflected ray escapes (the
// sphere is convex), so the sphere shows exactly r * L, whatever the integrator.
TEST(AnalyticScenes, DiffuseSphereInUniformEnvironmentIsAlbedoTimesL) {
  const float r = 0.5f, l = 2.0f;
  for (const char* integrator : {"mis", "bsdf", "nee"}) {
    Scene scene = SceneFromJson(R"({
      "render": {"width": 24, "height": 24, "spp": 64, "max_depth": 5, "seed": 7},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 20},
      "background": [2, 2, 2],
      "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1.2, "material": "m"}]
    })");
    RenderOptions opt;
    opt.integrator = std::string(integrator) == "mis"    ? IntegratorMode::kMis
                     : std::string(integrator) == "bsdf" ? IntegratorMode::kBsdf
                                                         : IntegratorMode::kNee;
    RenderResult res = RenderOnCpu(scene, opt);
    // The central 8x8 pixels see only the sphere. Tolerance: 3.89 standard deviations of the
    // window mean (false alarm 1e-4 per check), from the film's per-pixel sample variance,
    // plus 1e-5 relative for float accumulation.
    for (int c = 0; c < 3; ++c) {
      WindowMean w = MeanOverWindow(res.image, c, 8, 8, 16, 16);
      double tol = kZ1e4 * std::sqrt(w.varianceOfMean) + 1e-5 * r * l;
      EXPECT_NEAR(w.mean, r * l, tol) << integrator << " channel " << c;
    }
  }
}

// A smooth glass sphere without absorption in a uniform environment is invisible: each
// sample's weight is exactly 1 (Fresnel choice probabilities cancel Fresnel factors, and the
// 1/eta^2 of entering cancels eta^2 of leaving), so every pixel equals L.
TEST(AnalyticScenes, NonAbsorbingGlassSphereIsInvisible) {
  Scene scene = SceneFromJson(R"({
    "render": {"width": 24, "height": 24, "spp": 16, "max_depth": 64, "seed": 3,
               "russian_roulette_depth": 1000},
    "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 30},
    "background": [1.5, 1.5, 1.5],
    "materials": {"glass": {"type": "dielectric", "ior": 1.5}},
    "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"}]
  })");
  RenderResult res = RenderOnCpu(scene);
  // Paths still inside after 64 bounces would be lost: with R <= 0.2 per internal hit at
  // the angles reached, that is below 0.2^60 per path - far under float precision.
  for (size_t i = 0; i < res.image.rgb.size(); ++i)
    ASSERT_NEAR(res.image.rgb[i], 1.5f, 1.5f * 1e-4f) << "pixel value " << i / 3;
}

// A point light of intensity I above a diffuse plane of albedo r: the plane's radiance at a
// point at distance d, where the light arrives at angle theta, is r/pi * I cos(theta) / d^2.
float PlaneRadiance(const Camera& cam, float x, float y, int size) {
  float sx = (2.0f * x / size - 1) * cam.tanHalfFovY * cam.aspect;
  float sy = (1.0f - 2.0f * y / size) * cam.tanHalfFovY;
  vec3 d = glm::normalize(cam.forward + sx * cam.right + sy * cam.up);
  vec3 p = cam.position + d * (-cam.position.y / d.y);  // where the ray meets y = 0
  vec3 toLight = vec3(1, 2, 0.5) - p;
  float dist2 = glm::dot(toLight, toLight);
  return 0.6f / kPi * 10.0f * (toLight.y / std::sqrt(dist2)) / dist2;
}

TEST(AnalyticScenes, PointLightAboveDiffusePlane) {
  Scene scene = SceneFromJson(R"({
    "render": {"width": 33, "height": 33, "spp": 256, "max_depth": 1, "seed": 1},
    "camera": {"position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60},
    "materials": {"m": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
    "objects": [{"type": "quad", "origin": [-20, 0, 20], "u": [40, 0, 0], "v": [0, 0, -40],
                 "material": "m"}],
    "lights": [{"type": "point", "position": [1, 2, 0.5], "intensity": [10, 10, 10]}]
  })");
  RenderResult res = RenderOnCpu(scene);
  for (int py : {4, 16, 28})
    for (int px : {4, 16, 28}) {
      // The pixel is a box filter: average the closed form over a 32x32 grid of the pixel
      // (midpoint rule; its error is far below the tolerance for this smooth function).
      double expected = 0.0;
      for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i)
          expected += PlaneRadiance(scene.camera, px + (i + 0.5f) / 32, py + (j + 0.5f) / 32, 33);
      expected /= 32 * 32;
      // The only randomness is the sub-pixel jitter: its variance is the film's sample
      // variance. 9 pixels at z = 4.42 (p = 1e-5 each): family false alarm 9e-5.
      size_t k = size_t(py) * 33 + px;
      double sigma = std::sqrt(res.image.variance[3 * k] / res.image.samples[k]);
      EXPECT_NEAR(res.image.rgb[3 * k], expected, kZ1e5 * sigma + 1e-4 * expected)
          << px << "," << py;
    }
}

}  // namespace
}  // namespace pt::test
