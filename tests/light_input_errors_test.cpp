// Bad lights are refused before anything renders: a negative, NaN or overflowing intensity or
// radiance, a spot cone outside (0, 180] degrees in full (outer_angle in (0, 90], inner below
// it), a zero spot axis; in JSON scenes and in glTF KHR_lights_punctual. Each run ends with
// exit status 2, a message naming the file and the field, and no output written.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"

namespace pt::test {
namespace {

std::string SceneWithLight(const std::string& light, const std::string& lamp = "[4, 4, 4]") {
  return R"({"render": {"width": 4, "height": 4, "spp": 1, "max_depth": 2},
    "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov_y": 45},
    "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                  "lamp": {"type": "emissive", "radiance": )" + lamp + R"(}},
    "objects": [{"type": "quad", "origin": [-1, 0, -1], "u": [0, 0, 2], "v": [2, 0, 0],
                 "material": "white"},
                {"type": "sphere", "center": [0, 2, 0], "radius": 0.2, "material": "lamp"}],
    "lights": [)" + light + "]}";
}

std::string Point(const std::string& intensity) {
  return R"({"type": "point", "position": [0, 1, 0], "intensity": )" + intensity + "}";
}

// Refused with exit 2, nothing written, and the message names `field`.
void ExpectRefused(const std::string& dir, const std::string& name, const std::string& text,
                   const std::string& field) {
  std::string path = WriteText(dir + "/" + name, text);
  ExpectRefusedWritingNothing(path, "", dir);
  std::string output;
  RunPathtracer("'" + path + "' -o " + dir + "/x.png --backend cpu --quiet", &output);
  EXPECT_NE(output.find(field), std::string::npos) << name << ": " << output;
}

TEST(LightInputErrors, JsonScenesRefuseBadLights) {
  std::string dir = TempDir();
  const std::string spot = R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0],
                                "intensity": [1, 1, 1], )";
  ExpectRefused(dir, "neg_point.json",
                SceneWithLight(Point("[1, -1, 1]")),
                "lights[0].intensity[1]");
  ExpectRefused(dir, "huge_point.json",
                SceneWithLight(Point("[1e39, 1, 1]")),
                "lights[0].intensity[0]");
  ExpectRefused(dir, "nan_point.json",
                SceneWithLight(Point("[NaN, 1, 1]")),
                "nan_point.json");
  ExpectRefused(dir, "neg_spot.json",
                SceneWithLight(R"({"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0],
                                   "intensity": [-2, 1, 1]})"),
                "lights[0].intensity[0]");
  ExpectRefused(dir, "zero_cone.json", SceneWithLight(spot + R"("outer_angle": 0})"),
                "lights[0].outer_angle");
  ExpectRefused(dir, "wide_cone.json", SceneWithLight(spot + R"("outer_angle": 120})"),
                "lights[0].outer_angle");
  ExpectRefused(dir, "inner_past_outer.json",
                SceneWithLight(spot + R"("inner_angle": 40, "outer_angle": 30})"),
                "lights[0].inner_angle");
  ExpectRefused(dir, "no_axis.json",
                SceneWithLight(R"({"type": "spot", "position": [0, 2, 0], "direction": [0, 0, 0],
                                   "intensity": [1, 1, 1]})"),
                "lights[0].direction");
  ExpectRefused(dir, "neg_lamp.json",
                SceneWithLight(Point("[1, 1, 1]"),
                               "[4, -1, 4]"),
                "materials.lamp.radiance[1]");
  ExpectRefused(dir, "neg_sun.json",
                SceneWithLight(R"({"type": "directional", "direction": [0, -1, 0],
                                   "irradiance": [1, 1, -3]})"),
                "lights[0].irradiance[2]");
}

TEST(LightInputErrors, GltfFilesRefuseBadPunctualLights) {
  std::string dir = TempDir();
  using Json = GltfSceneWriter::Json;
  const double kPi = 3.14159265358979;
  struct Case {
    const char* name;
    Json light;
    const char* field;
  };
  const Case cases[] = {
      {"neg_intensity", {{"type", "point"}, {"intensity", -1.0}}, "lights[0].intensity"},
      {"neg_colour", {{"type", "point"}, {"color", {1, -0.5, 1}}}, "lights[0].color"},
      {"zero_cone",
       {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", 0.0}}}},
       "lights[0].spot"},
      {"wide_cone",
       {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.6 * kPi}}}},
       "lights[0].spot"},
  };
  for (const Case& c : cases) {
    GltfSceneWriter w;
    w.AddNode({{"mesh", w.AddFloor(5.0f)}});
    w.AddNode(GltfSceneWriter::LightNode(w.AddLight(c.light)));
    std::string file = w.Write(dir, c.name);
    ExpectRefusedWritingNothing(file, "", dir);
    std::string output;
    RunPathtracer("'" + file + "' -o " + dir + "/x.png --backend cpu --quiet", &output);
    EXPECT_NE(output.find(c.field), std::string::npos) << c.name << ": " << output;
  }
}

}  // namespace
}  // namespace pt::test
