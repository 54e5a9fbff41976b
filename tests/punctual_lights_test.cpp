// glTF KHR_lights_punctual and the scene format's spot and directional lights against their
// closed forms over a diffuse plane of albedo r: a point light gives r/pi I cos / d^2, a spot
// the same times the spec's cone falloff, a directional light r/pi E cos everywhere. The
// lights come from a generated glTF (node transforms placing and aiming them) and from JSON.
#include <gtest/gtest.h>

#include <functional>

#include "src/lights/light_table.h"
#include "tests/gltf_scene_writer.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::test {
namespace {

using GltfJson = GltfSceneWriter::Json;

constexpr float kAlbedo = 0.6f;
constexpr int kSize = 33;

// The falloff KHR_lights_punctual's specification recommends, written from it.
double SpecSpotFalloff(double cosAngle, double innerRadians, double outerRadians) {
  double scale = 1.0 / std::max(0.001, std::cos(innerRadians) - std::cos(outerRadians));
  double offset = -std::cos(outerRadians) * scale;
  double t = std::clamp(cosAngle * scale + offset, 0.0, 1.0);
  return t * t;
}

// dir/lights.gltf: the floor y = 0 (half size 20) and one light node.
std::string WriteLightFile(const std::string& dir, const GltfJson& light, const GltfJson& node) {
  GltfSceneWriter w;
  w.AddNode({{"mesh", w.AddFloor(20.0f)}});
  w.AddNode(GltfSceneWriter::LightNode(w.AddLight(light), node));
  return w.Write(dir, "lights");
}

// A camera 10 above the floor looking down, the floor diffuse (the file's material replaced).
Scene FloorScene(const std::string& dir, const std::string& lightsJson) {
  std::string text = R"({
    "render": {"width": 33, "height": 33, "spp": 256, "max_depth": 1, "seed": 1},
    "camera": {"position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60},
    "materials": {"m": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]}},
    "objects": [{"type": "mesh", "file": "lights.gltf", "material": "m"}],
    "lights": )" + lightsJson + "}";
  return BuildScene(LoadSceneFromString(text, "floor.json", dir));
}

// Where the ray through image point (x, y) meets the floor.
vec3 FloorAt(const Camera& cam, double x, double y) {
  float sx = float((2.0 * x / kSize - 1) * cam.tanHalfFovY * cam.aspect);
  float sy = float((1.0 - 2.0 * y / kSize) * cam.tanHalfFovY);
  vec3 d = glm::normalize(cam.forward + sx * cam.right + sy * cam.up);
  return cam.position + d * (-cam.position.y / d.y);
}

// Every pixel of the middle row and column against the closed form averaged over the pixel
// (a box filter; 16 x 16 midpoint rule). The only randomness is the sub-pixel jitter, whose
// variance is the film's: 65 pixels x 3 channels at a family false-alarm rate of 1e-4.
void ExpectFloorRadiance(const Scene& scene, const std::function<vec3(vec3)>& radiance) {
  RenderResult res = RenderOnCpu(scene);
  const double z = TwoSidedNormalQuantile(1e-4 / (65 * 3));
  int checked = 0;
  for (int i = 0; i < kSize * 2; ++i) {
    int px = i < kSize ? i : kSize / 2, py = i < kSize ? kSize / 2 : i - kSize;
    if (i >= kSize && py == kSize / 2) continue;  // the centre, checked once
    glm::dvec3 expected(0.0);
    for (int j = 0; j < 16; ++j)
      for (int k = 0; k < 16; ++k)
        expected += glm::dvec3(radiance(FloorAt(scene.camera, px + (k + 0.5) / 16, py + (j + 0.5) / 16)));
    expected /= 256.0;
    size_t p = size_t(py) * kSize + px;
    for (int c = 0; c < 3; ++c) {
      double sigma = std::sqrt(res.image.variance[3 * p + c] / res.image.samples[p]);
      EXPECT_NEAR(res.image.rgb[3 * p + c], expected[c], z * sigma + 1e-4 * expected[c] + 1e-7)
          << "pixel " << px << "," << py << " channel " << c;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 65);
}

vec3 PointRadiance(vec3 p, vec3 position, vec3 intensity) {
  vec3 toLight = position - p;
  float d2 = glm::dot(toLight, toLight);
  return kAlbedo / kPi * intensity * (toLight.y / std::sqrt(d2)) / d2;
}

TEST(PunctualLights, GltfPointLightIsIntensityTimesColourOverDistanceSquared) {
  std::string dir = TempDir();
  WriteLightFile(dir, {{"type", "point"}, {"intensity", 10}, {"color", {1, 0.5, 0.25}}},
                 {{"translation", {1, 2, 0.5}}});
  Scene scene = FloorScene(dir, "[]");
  ASSERT_EQ(scene.desc.pointLights.size(), 1u);
  ExpectFloorRadiance(scene, [](vec3 p) {
    return PointRadiance(p, vec3(1, 2, 0.5f), vec3(10, 5, 2.5f));
  });
}

// A spot 3 above the floor aimed straight down (the node turns its -Z to -Y): full inside
// 20 degrees, nothing beyond 40, the spec's smooth falloff between; the row crosses all three.
vec3 SpotRadiance(vec3 p, vec3 intensity) {
  vec3 position(0, 3, 0);
  float cosAxis = glm::normalize(p - position).y * -1.0f;
  return PointRadiance(p, position, intensity) *
         float(SpecSpotFalloff(cosAxis, 20 * kDeg, 40 * kDeg));
}

TEST(PunctualLights, GltfSpotLightFallsOffBetweenItsCones) {
  std::string dir = TempDir();
  WriteLightFile(dir,
                 {{"type", "spot"}, {"intensity", 8},
                  {"spot", {{"innerConeAngle", 20 * kDeg}, {"outerConeAngle", 40 * kDeg}}}},
                 {{"translation", {0, 3, 0}}, {"rotation", GltfRotation(-90, {1, 0, 0})}});
  Scene scene = FloorScene(dir, "[]");
  ASSERT_EQ(scene.desc.spotLights.size(), 1u);
  ExpectFloorRadiance(scene, [](vec3 p) { return SpotRadiance(p, vec3(8)); });
}

TEST(PunctualLights, JsonSpotLightEqualsTheGltfOne) {
  std::string dir = TempDir();
  WriteLightFile(dir, {{"type", "point"}, {"intensity", 0}}, GltfJson::object());  // dark
  Scene scene = FloorScene(dir, R"([{"type": "spot", "position": [0, 3, 0],
      "direction": [0, -1, 0], "intensity": [8, 4, 2], "inner_angle": 20, "outer_angle": 40}])");
  ExpectFloorRadiance(scene, [](vec3 p) { return SpotRadiance(p, vec3(8, 4, 2)); });
}

// The falloff at the spec's landmarks: 1 inside the inner cone, 0 at the outer, 1/4 where
// the cosine is half way between the cones' cosines (the ramp is squared).
TEST(PunctualLights, SpotFalloffLandmarks) {
  SpotLightDesc desc;
  desc.innerAngle = float(20 * kDeg);
  desc.outerAngle = float(40 * kDeg);
  Light spot = MakeSpotLight(desc);
  double ci = std::cos(20 * kDeg), co = std::cos(40 * kDeg);
  EXPECT_FLOAT_EQ(spot.SpotFalloff(1.0f), 1.0f);
  EXPECT_NEAR(spot.SpotFalloff(float(ci)), 1.0f, 1e-5f);
  EXPECT_NEAR(spot.SpotFalloff(float(co)), 0.0f, 1e-5f);
  EXPECT_EQ(spot.SpotFalloff(float(std::cos(41 * kDeg))), 0.0f);
  EXPECT_NEAR(spot.SpotFalloff(float(0.5 * (ci + co))), 0.25f, 1e-5f);
}

// The light table's power of a spot is its intensity times the falloff's integral over the
// sphere (here by a fine midpoint rule in the cosine), so it is chosen in proportion.
TEST(PunctualLights, SpotPowerIsTheFalloffIntegratedOverTheSphere) {
  for (double outer : {10.0, 45.0, 90.0}) {
    Scene scene = SceneFromJson(R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40},
        "materials": {}, "objects": [],
        "lights": [{"type": "spot", "position": [0, 0, 0], "direction": [1, 1, 0],
                    "intensity": [2, 2, 2], "inner_angle": 5, "outer_angle": )" +
                                std::to_string(outer) + "}]}");
    ASSERT_EQ(scene.lights.size(), 1u);
    const int n = 200000;
    double integral = 0.0;
    for (int i = 0; i < n; ++i) {
      double c = -1.0 + 2.0 * (i + 0.5) / n;
      integral += SpecSpotFalloff(c, 5 * kDeg, outer * kDeg) * 2.0 / n;
    }
    integral *= 2.0 * kPi;
    EXPECT_NEAR(LightPower(scene, scene.lights[0]), 2.0 * integral, 1e-5 * integral) << outer;
  }
}

// Light travels along the node's -Z, here turned by -60 degrees about X so that it arrives
// 30 degrees from the floor's normal: r / pi E cos(30 deg) on every pixel. No randomness
// reaches the floor's radiance, so the tolerance is float accumulation only.
TEST(PunctualLights, GltfDirectionalLightIsIrradianceTimesCosine) {
  std::string dir = TempDir();
  WriteLightFile(dir, {{"type", "directional"}, {"intensity", 3}, {"color", {1, 1, 0.5}}},
                 {{"translation", {50, 50, 50}}, {"rotation", GltfRotation(-60, {1, 0, 0})}});
  Scene scene = FloorScene(dir, "[]");
  ASSERT_EQ(scene.desc.directionalLights.size(), 1u);
  vec3 toLight = scene.desc.directionalLights[0].direction;
  EXPECT_NEAR(toLight.y, std::sin(60 * kDeg), 1e-6);
  EXPECT_NEAR(toLight.z, std::cos(60 * kDeg), 1e-6);
  vec3 expected = kAlbedo / kPi * vec3(3, 3, 1.5f) * float(std::sin(60 * kDeg));
  RenderResult res = RenderOnCpu(scene);
  for (size_t i = 0; i < res.image.rgb.size(); ++i) {
    ASSERT_NEAR(res.image.rgb[i], expected[i % 3], 1e-5 * expected[i % 3]) << "value " << i;
  }
}

TEST(PunctualLights, FileLightsFollowTheObjectTransformAndCanBeLeftOut) {
  std::string dir = TempDir();
  WriteLightFile(dir, {{"type", "spot"}, {"intensity", 2}, {"spot", GltfJson::object()}},
                 {{"translation", {0, 3, 0}}, {"rotation", GltfRotation(-90, {1, 0, 0})}});
  auto load = [&](const std::string& extra) {
    return LoadSceneFromString(R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 1},
        "camera": {"position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 60},
        "materials": {}, "objects": [{"type": "mesh", "file": "lights.gltf",
          "transform": {"rotate": [0, 0, 90], "translate": [5, 0, 0]})" + extra + "}]}",
                               "t.json", dir);
  };
  SceneDesc with = load("");
  ASSERT_EQ(with.spotLights.size(), 1u);
  const SpotLightDesc& s = with.spotLights[0];
  // Rotating 90 degrees about Z takes (0, 3, 0) to (-3, 0, 0) and down (-Y) to +X.
  EXPECT_NEAR(s.position.x, 2.0f, 1e-5f);
  EXPECT_NEAR(s.position.y, 0.0f, 1e-5f);
  EXPECT_NEAR(s.direction.x, 1.0f, 1e-6f);
  EXPECT_NEAR(s.direction.y, 0.0f, 1e-6f);
  EXPECT_TRUE(load(R"(, "lights_from_file": false)").spotLights.empty());
}

}  // namespace
}  // namespace pt::test
