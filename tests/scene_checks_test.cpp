// Warnings for scenes that render black for a reason the user can fix (src/scene/scene_checks):
// no light, nothing to see, and one-sided emitters that face away from everything.
#include <gtest/gtest.h>

#include "src/io/scene_loader.h"
#include "src/scene/scene_checks.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// A floor at y = 0 seen from above, and whatever light the test adds.
Scene FloorWith(const std::string& materials, const std::string& objects,
                const std::string& extra = "") {
  std::string text = R"({"render": {"width": 8, "height": 8, "spp": 1, "max_depth": 2},
    "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov_y": 45},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})" +
                     materials + R"(},
    "objects": [{"type": "quad", "origin": [-1, 0, 1], "u": [2, 0, 0], "v": [0, 0, -2],
                 "material": "white"})" +
                     objects + "]" + extra + "}";
  return BuildScene(LoadSceneFromString(text, "test.json", "."));
}

// A lamp quad at height 2 over the floor; facing down (lights the floor) unless flipped.
std::string Lamp(bool facingDown, const std::string& material = "lamp") {
  std::string u = facingDown ? "[1, 0, 0]" : "[0, 0, 1]", v = facingDown ? "[0, 0, 1]" : "[1, 0, 0]";
  return R"(, {"type": "quad", "origin": [-0.5, 2, -0.5], "u": )" + u + R"(, "v": )" + v +
         R"(, "material": ")" + material + "\"}";
}

const std::string kLamp = R"(, "lamp": {"type": "emissive", "radiance": [5, 5, 5]})";

bool Mentions(const std::vector<std::string>& warnings, const std::string& part) {
  for (const std::string& w : warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST(SceneChecks, ALitSceneHasNoWarning) {
  EXPECT_TRUE(DarkSceneWarnings(FloorWith(kLamp, Lamp(true))).empty());
  SceneDesc cornell = LoadScene(test::SourcePath("scenes/cornell_box.json"));
  EXPECT_TRUE(DarkSceneWarnings(BuildScene(std::move(cornell))).empty());
}

TEST(SceneChecks, NoLightAtAll) {
  std::vector<std::string> w = DarkSceneWarnings(FloorWith("", ""));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(Mentions(w, "the scene has no light")) << w[0];
  // An emitter of zero radiance and a point light of zero intensity are no light either.
  std::string dark = R"(, "lamp": {"type": "emissive", "radiance": [0, 0, 0]})";
  std::string zeroPoint = R"(, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": [0, 0, 0]}])";
  EXPECT_TRUE(Mentions(DarkSceneWarnings(FloorWith(dark, Lamp(true), zeroPoint)), "no light"));
  // A background alone lights the scene.
  EXPECT_TRUE(DarkSceneWarnings(FloorWith("", "", R"(, "background": [0.2, 0.2, 0.2])")).empty());
}

TEST(SceneChecks, SunsSkiesAndMapsAreLight) {
  std::string sun = R"(, "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 2, 2]}])";
  EXPECT_TRUE(DarkSceneWarnings(FloorWith("", "", sun)).empty());
  std::string sky = R"(, "environment": {"sky": {"sun_elevation": 40, "width": 16}})";
  EXPECT_TRUE(DarkSceneWarnings(FloorWith("", "", sky)).empty());
  // A sun of zero irradiance lights nothing.
  std::string darkSun = R"(, "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [0, 0, 0]}])";
  EXPECT_TRUE(Mentions(DarkSceneWarnings(FloorWith("", "", darkSun)), "no light"));
}

TEST(SceneChecks, AnEnvironmentIsSeenWithoutObjects) {
  auto warnings = [](const std::string& lighting) {
    std::string text = R"({"render": {"width": 8, "height": 8, "spp": 1, "max_depth": 2},
      "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov_y": 45},
      "materials": {}, "objects": [])" + lighting + "}";
    return DarkSceneWarnings(BuildScene(LoadSceneFromString(text, "t.json", ".")));
  };
  EXPECT_TRUE(warnings(R"(, "environment": {"sky": {"sun_elevation": 40, "width": 16}})").empty());
  // Hidden from the camera, it shows the camera colour: black is nothing to see.
  EXPECT_TRUE(Mentions(warnings(R"(, "environment": {"radiance": [1, 1, 1], "visible_to_camera": false})"),
                       "no objects"));
  EXPECT_TRUE(warnings(R"(, "environment": {"radiance": [1, 1, 1], "visible_to_camera": false,
                           "camera_color": [0.2, 0.2, 0.2]})").empty());
  // A delta sun is never seen; a sun's disk is.
  std::string sun = R"(, "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 2, 2]}])";
  EXPECT_TRUE(Mentions(warnings(sun), "no objects"));
  std::string disk = R"(, "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 2, 2], "angular_radius": 1}])";
  EXPECT_TRUE(warnings(disk).empty());
}

TEST(SceneChecks, PointLightsWithNothingToSee) {
  std::string text = R"({"render": {"width": 8, "height": 8, "spp": 1, "max_depth": 2},
    "camera": {"position": [0, 1, 3], "look_at": [0, 0.5, 0], "fov_y": 45},
    "materials": {}, "objects": [],
    "lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, 1]}]})";
  std::vector<std::string> w = DarkSceneWarnings(BuildScene(LoadSceneFromString(text, "t.json", ".")));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(Mentions(w, "no objects and a black background")) << w[0];
}

TEST(SceneChecks, AnEmitterFacingAwayFromEverything) {
  // The lamp faces up, away from the floor below it and the camera below its plane.
  std::vector<std::string> w = DarkSceneWarnings(FloorWith(kLamp, Lamp(false)));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(Mentions(w, "emissive material \"lamp\" faces away")) << w[0];
  EXPECT_TRUE(Mentions(w, "two_sided")) << w[0];
  // Two-sided, it lights the floor.
  std::string twoSided = R"(, "lamp": {"type": "emissive", "radiance": [5, 5, 5], "two_sided": true})";
  EXPECT_TRUE(DarkSceneWarnings(FloorWith(twoSided, Lamp(false))).empty());
  // Something above it (a diffuse ceiling) is lit by it.
  std::string ceiling = R"(, {"type": "quad", "origin": [-1, 3, -1], "u": [2, 0, 0], "v": [0, 0, 2], "material": "white"})";
  EXPECT_TRUE(DarkSceneWarnings(FloorWith(kLamp, Lamp(false) + ceiling)).empty());
  // One face of a material lighting the floor is enough: the material is not warned about.
  EXPECT_TRUE(DarkSceneWarnings(FloorWith(kLamp, Lamp(false) + Lamp(true))).empty());
}

TEST(SceneChecks, AnEmitterFacingTheCameraOnlyIsSeen) {
  // A lamp on the floor facing +z: nothing lies in front of it, but the camera (z = 3) does.
  std::string lamp = R"(, {"type": "quad", "origin": [-0.2, 0, 0], "u": [0.4, 0, 0], "v": [0, 0.4, 0], "material": "lamp"})";
  EXPECT_TRUE(DarkSceneWarnings(FloorWith(kLamp, lamp)).empty());
  // At the floor's far edge facing -z, away from the camera and the floor (which only
  // touches its plane).
  std::string away = R"(, {"type": "quad", "origin": [-0.2, 0, -1], "u": [0, 0.4, 0], "v": [0.4, 0, 0], "material": "lamp"})";
  EXPECT_TRUE(Mentions(DarkSceneWarnings(FloorWith(kLamp, away)), "\"lamp\" faces away"));
}

}  // namespace
}  // namespace pt
