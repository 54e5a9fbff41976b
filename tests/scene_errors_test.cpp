// Every error rule of the scene format: each throws SceneError naming the file and the field.
#include <gtest/gtest.h>

#include <fstream>

#include "src/io/scene_loader.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// A valid scene with one sphere; each test swaps in one bad piece.
struct Parts {
  std::string format = "";
  std::string render = R"("width": 4, "height": 2, "spp": 1, "max_depth": 1)";
  std::string camera = R"("position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 45)";
  std::string materials = R"("white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]})";
  std::string objects = R"({"type": "sphere", "center": [0, 0, -3], "radius": 1, "material": "white"})";
  std::string extra = "";

  std::string Text() const {
    return "{" + format + R"("render": {)" + render + R"(}, "camera": {)" + camera +
           R"(}, "materials": {)" + materials + R"(}, "objects": [)" + objects + "]" + extra + "}";
  }
};

std::string ErrorOf(const std::string& text, const std::string& baseDir = test::SourcePath("scenes")) {
  try {
    LoadSceneFromString(text, "scenes/bad.json", baseDir);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

// The message starts with the file and names the field path; 'detail' is part of the reason.
void ExpectError(const Parts& parts, const std::string& field, const std::string& detail) {
  std::string message = ErrorOf(parts.Text());
  EXPECT_EQ(message.rfind("scenes/bad.json: ", 0), 0u) << message;
  EXPECT_NE(message.find(field), std::string::npos) << "field '" << field << "' in: " << message;
  EXPECT_NE(message.find(detail), std::string::npos) << "'" << detail << "' in: " << message;
}

Parts WithMaterial(const std::string& material) {
  Parts p;
  p.materials = R"("m": )" + material;
  p.objects = R"({"type": "sphere", "center": [0, 0, -3], "radius": 1, "material": "m"})";
  return p;
}

Parts WithObject(const std::string& object) {
  Parts p;
  p.objects = object;
  return p;
}

Parts WithSphereTransform(const std::string& transform) {
  return WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                        "transform": )" + transform + "}");
}

TEST(SceneErrors, ValidBaseSceneLoads) { EXPECT_EQ(ErrorOf(Parts().Text()), "(no error)"); }

TEST(SceneErrors, ExactMessageForAlbedoOutOfRange) {
  Parts p;
  p.materials = R"("white": {"type": "diffuse", "albedo": [0.5, 1.3, 0.5]})";
  EXPECT_EQ(ErrorOf(p.Text()), "scenes/bad.json: materials.white.albedo[1]: 1.3 is outside [0, 1]");
}

TEST(SceneErrors, UnknownFields) {
  Parts top;
  top.extra = R"(, "objekts": [])";
  ExpectError(top, "objekts", "unknown field");
  Parts render;
  render.render += R"(, "sample_count": 4)";
  ExpectError(render, "render.sample_count", "unknown field");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": [1, 1, 1], "shininess": 3})"),
              "materials.m.shininess", "unknown field");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": [1, 1, 1], "ior": 1.5})"),
              "materials.m.ior", "a diffuse material has");
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "white",
                             "colour": [1, 0, 0]})"), "objects[0].colour", "unknown field");
  ExpectError(WithSphereTransform(R"({"rotation": [0, 1, 0]})"), "objects[0].transform.rotation",
              "unknown field");
}

TEST(SceneErrors, DuplicateKeys) {
  Parts top;
  top.extra = R"(, "render": {"width": 4, "height": 2, "spp": 1, "max_depth": 1})";
  ExpectError(top, "render", "duplicate key \"render\"");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": [1, 1, 1], "albedo": [0, 0, 0]})"),
              "materials.m.albedo", "duplicate key \"albedo\" in materials.m");
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "radius": 2,
                             "material": "white"})"), "objects[0].radius", "duplicate key");
}

TEST(SceneErrors, MissingRequiredFields) {
  Parts width;
  width.render = R"("height": 2, "spp": 1, "max_depth": 1)";
  ExpectError(width, "render.width", "missing required field");
  Parts fov;
  fov.camera = R"("position": [0, 0, 0], "look_at": [0, 0, -1])";
  ExpectError(fov, "camera.fov_y", "missing required field");
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1})"),
              "objects[0].material", "missing required field");
  ExpectError(WithObject(R"({"type": "mesh", "material": "white"})"), "objects[0].file",
              "missing required field");
  ExpectError(WithMaterial(R"({"type": "emissive"})"), "materials.m.radiance", "missing");
  ExpectError(WithMaterial(R"({"albedo": [1, 1, 1]})"), "materials.m.type", "missing");
  Parts adaptive;
  adaptive.render += R"(, "adaptive": {"tolerance": 0.1, "min_spp": 1})";
  ExpectError(adaptive, "render.adaptive.batch", "missing required field");
  std::string noObjects = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 45}, "materials": {}})";
  EXPECT_NE(ErrorOf(noObjects).find("scenes/bad.json: objects: missing"), std::string::npos)
      << ErrorOf(noObjects);
}

TEST(SceneErrors, WrongTypes) {
  Parts width;
  width.render = R"("width": "512", "height": 2, "spp": 1, "max_depth": 1)";
  ExpectError(width, "render.width", "expected an integer, got string");
  Parts spp;
  spp.render = R"("width": 4, "height": 2, "spp": 1.5, "max_depth": 1)";
  ExpectError(spp, "render.spp", "expected an integer");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": 0.5})"), "materials.m.albedo",
              "expected an array of 3 numbers");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": [1, 1]})"), "materials.m.albedo",
              "expected an array of 3 numbers");
  ExpectError(WithMaterial(R"({"type": "emissive", "radiance": [1, 1, 1], "two_sided": "yes"})"),
              "materials.m.two_sided", "expected true or false");
  ExpectError(WithMaterial(R"({"type": "diffuse", "albedo": [1, null, 1]})"),
              "materials.m.albedo[1]", "expected a number");
  ExpectError(WithObject(R"({"type": "mesh", "file": 3})"), "objects[0].file", "expected a string");
  Parts objects;
  objects.extra = "";
  objects.objects = "";
  std::string text = objects.Text();
  text.replace(text.find("\"objects\": []"), 13, "\"objects\": {}");
  EXPECT_NE(ErrorOf(text).find("objects: expected an array, got object"), std::string::npos)
      << ErrorOf(text);
}

TEST(SceneErrors, NonFiniteNumbers) {
  ExpectError(WithMaterial(R"({"type": "emissive", "radiance": [1e999, 1, 1]})"),
              "materials.m.radiance[0]", "not a finite number");
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, -1e400, 0], "radius": 1,
                             "material": "white"})"), "objects[0].center[1]", "not a finite number");
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1e300,
                             "material": "white"})"), "objects[0].radius", "too large for a float");
}

TEST(SceneErrors, OutOfRangeNumbers) {
  auto sphereRadius = [](const char* r) {
    return WithObject(std::string(R"({"type": "sphere", "center": [0, 0, 0], "material": "white", "radius": )") + r + "}");
  };
  ExpectError(sphereRadius("-1"), "objects[0].radius", "-1 must be > 0");
  ExpectError(sphereRadius("0"), "objects[0].radius", "0 must be > 0");
  ExpectError(WithMaterial(R"({"type": "dielectric", "ior": 0})"), "materials.m.ior", "must be > 0");
  ExpectError(WithMaterial(R"({"type": "dielectric", "ior": -1.5})"), "materials.m.ior", "must be > 0");
  ExpectError(WithMaterial(R"({"type": "dielectric", "ior": 1.5, "absorption": [0, -1, 0]})"),
              "materials.m.absorption[1]", "must be >= 0");
  ExpectError(WithMaterial(R"({"type": "conductor", "albedo": [-0.1, 0, 0]})"),
              "materials.m.albedo[0]", "outside [0, 1]");
  ExpectError(WithMaterial(R"({"type": "conductor", "albedo": [1, 1, 1], "roughness": 1.5})"),
              "materials.m.roughness", "outside [0, 1]");
  ExpectError(WithMaterial(R"({"type": "emissive", "radiance": [1, -2, 1]})"),
              "materials.m.radiance[1]", "must be >= 0");
  Parts light;
  light.extra = R"(, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": [1, 1, -1]}])";
  ExpectError(light, "lights[0].intensity[2]", "must be >= 0");
  Parts background;
  background.extra = R"(, "background": [0, -0.5, 0])";
  ExpectError(background, "background[1]", "must be >= 0");
}

TEST(SceneErrors, OutOfRangeRenderAndCamera) {
  auto render = [](const std::string& r) { Parts p; p.render = r; return p; };
  ExpectError(render(R"("width": 0, "height": 2, "spp": 1, "max_depth": 1)"), "render.width", "outside");
  ExpectError(render(R"("width": 4, "height": -1, "spp": 1, "max_depth": 1)"), "render.height", "outside");
  ExpectError(render(R"("width": 100000, "height": 100000, "spp": 1, "max_depth": 1)"),
              "render.width", "too large");
  ExpectError(render(R"("width": 4, "height": 2, "spp": 0, "max_depth": 1)"), "render.spp", "outside");
  ExpectError(render(R"("width": 4, "height": 2, "spp": 16777217, "max_depth": 1)"), "render.spp",
              "outside");
  ExpectError(render(R"("width": 4, "height": 2, "spp": 1, "max_depth": -1)"), "render.max_depth",
              "outside");
  // The path state counts depth in 12 bits: 4096 would carry into its flags.
  ExpectError(render(R"("width": 4, "height": 2, "spp": 1, "max_depth": 4096)"), "render.max_depth",
              "outside");
  EXPECT_EQ(ErrorOf(render(R"("width": 4, "height": 2, "spp": 1, "max_depth": 4095)").Text()),
            "(no error)");
  ExpectError(render(R"("width": 4, "height": 2, "spp": 1, "max_depth": 1, "seed": -1)"),
              "render.seed", "outside");
  ExpectError(render(R"("width": 4, "height": 2, "spp": 1, "max_depth": 1, "russian_roulette_depth": -2)"),
              "render.russian_roulette_depth", "outside");
  const std::string base = R"("width": 4, "height": 2, "spp": 64, "max_depth": 1, )";
  ExpectError(render(base + R"("adaptive": {"tolerance": 0, "min_spp": 1, "batch": 1})"),
              "render.adaptive.tolerance", "outside (0, 1]");
  ExpectError(render(base + R"("adaptive": {"tolerance": 0.1, "min_spp": 128, "batch": 1})"),
              "render.adaptive.min_spp", "exceeds render.spp");
  ExpectError(render(base + R"("adaptive": {"tolerance": 0.1, "min_spp": 1, "batch": 0})"),
              "render.adaptive.batch", "outside");
  auto camera = [](const std::string& c) { Parts p; p.camera = c; return p; };
  const std::string pos = R"("position": [0, 0, 0], "look_at": [0, 0, -1], )";
  ExpectError(camera(pos + R"("fov_y": 0)"), "camera.fov_y", "outside (0, 180)");
  ExpectError(camera(pos + R"("fov_y": 180)"), "camera.fov_y", "outside (0, 180)");
  ExpectError(camera(pos + R"("fov_y": 45, "aperture_radius": -0.1)"), "camera.aperture_radius", ">= 0");
  ExpectError(camera(pos + R"("fov_y": 45, "focus_distance": 0)"), "camera.focus_distance", "> 0");
}

// JSON has no NaN or Infinity: the message names the element that holds one, not the last
// good element before it (a NaN at look_at[1] once read "malformed JSON near look_at[0]").
TEST(SceneErrors, NonFiniteLiteralsNameTheirExactIndex) {
  const std::string head = "scenes/bad.json: ";
  auto lookAt = [](const std::string& v) {
    Parts p;
    p.camera = R"("position": [0, 0, 0], "look_at": )" + v + R"(, "fov_y": 45)";
    return p;
  };
  EXPECT_EQ(ErrorOf(lookAt("[0, NaN, -1]").Text()),
            head + "camera.look_at[1]: NaN is not a finite number (JSON has no NaN or Infinity)");
  EXPECT_EQ(ErrorOf(lookAt("[NaN, 0, -1]").Text()).rfind(head + "camera.look_at[0]: NaN", 0), 0u);
  EXPECT_EQ(ErrorOf(lookAt("[0, 0,\n  -Infinity]").Text()).rfind(head + "camera.look_at[2]: -Infinity", 0),
            0u);
  EXPECT_EQ(ErrorOf(lookAt("[0, inf, -1]").Text()).rfind(head + "camera.look_at[1]: inf", 0), 0u);
  Parts fov;
  fov.camera = R"("position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": nan)";
  EXPECT_EQ(ErrorOf(fov.Text()).rfind(head + "camera.fov_y: nan is not a finite number", 0), 0u);
  // Other broken values still read as malformed JSON near the element that failed.
  std::string typo = ErrorOf(lookAt("[0, 1x, -1]").Text());
  EXPECT_EQ(typo.rfind(head + "malformed JSON near camera.look_at[1]", 0), 0u) << typo;
}

TEST(SceneErrors, CameraUpParallelOrNoViewDirection) {
  Parts up;
  up.camera = R"("position": [0, 0, 0], "look_at": [0, 5, 0], "up": [0, 2, 0], "fov_y": 45)";
  ExpectError(up, "camera.up", "parallel to the view direction");
  Parts down;
  down.camera = R"("position": [0, 0, 0], "look_at": [0, -5, 0], "fov_y": 45)";
  ExpectError(down, "camera.up", "parallel");
  Parts same;
  same.camera = R"("position": [1, 2, 3], "look_at": [1, 2, 3], "fov_y": 45)";
  ExpectError(same, "camera.look_at", "equals camera.position");
}

TEST(SceneErrors, UndefinedMaterial) {
  ExpectError(WithObject(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "gold"})"),
              "objects[0].material", "undefined material \"gold\"");
  ExpectError(WithObject(R"({"type": "mesh", "file": "meshes/smooth_shapes.glb", "material": "x"})"),
              "objects[0].material", "undefined material");
}

TEST(SceneErrors, UnknownTypes) {
  ExpectError(WithObject(R"({"type": "cylinder", "material": "white"})"), "objects[0].type",
              "unknown object type \"cylinder\"");
  ExpectError(WithMaterial(R"({"type": "velvet"})"), "materials.m.type", "unknown material type");
  Parts light;
  light.extra = R"(, "lights": [{"type": "tube", "position": [0, 1, 0], "intensity": [1, 1, 1]}])";
  ExpectError(light, "lights[0].type", "unknown light type");
}

TEST(SceneErrors, LaterFormatRefusedByName) {
  Parts later;
  later.format = R"("format": 2, )";
  later.extra = R"(, "future_field": true)";  // refused as a later format, not as unknown
  ExpectError(later, "format", "format 2 is newer");
  Parts zero;
  zero.format = R"("format": 0, )";
  ExpectError(zero, "format", "not a format version");
}

TEST(SceneErrors, BadMatrices) {
  ExpectError(WithSphereTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]})"),
              "objects[0].transform.matrix", "last row must be 0 0 0 1");
  ExpectError(WithSphereTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0]})"),
              "objects[0].transform.matrix", "expected 16 numbers");
  ExpectError(WithSphereTransform(R"({"matrix": [1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1]})"),
              "objects[0].transform.matrix", "singular");
  ExpectError(WithSphereTransform(R"({"scale": [1, 0, 1]})"), "objects[0].transform.scale[1]",
              "must be non-zero");
}

TEST(SceneErrors, BothTransformForms) {
  ExpectError(WithSphereTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
                                      "translate": [1, 0, 0]})"),
              "objects[0].transform.translate", "cannot be combined");
}

TEST(SceneErrors, NonUniformScaleOnSphere) {
  ExpectError(WithSphereTransform(R"({"scale": [1, 2, 1]})"), "objects[0].transform.scale",
              "only a uniform scale");
  ExpectError(WithSphereTransform(R"({"matrix": [1,0,0,0, 0,3,0,0, 0,0,1,0, 0,0,0,1]})"),
              "objects[0].transform.matrix", "only a uniform scale");
}

TEST(SceneErrors, DegenerateShapes) {
  ExpectError(WithObject(R"({"type": "quad", "origin": [0, 0, 0], "u": [1, 0, 0], "v": [2, 0, 0],
                             "material": "white"})"), "objects[0].v", "no area");
  ExpectError(WithObject(R"({"type": "box", "min": [0, 0, 0], "max": [1, 0, 1], "material": "white"})"),
              "objects[0].max", "must exceed min");
}

TEST(SceneErrors, MeshFiles) {
  ExpectError(WithObject(R"({"type": "mesh", "file": "meshes/no_such_file.glb"})"), "objects[0].file",
              "no such file");
  ExpectError(WithObject(R"({"type": "mesh", "file": "meshes/bunny.ply"})"), "objects[0].file",
              "unsupported mesh format \".ply\"");
  std::string dir = test::TempDir();
  std::ofstream(dir + "/broken.glb") << "glTF this is not a binary glTF";
  Parts broken = WithObject(R"({"type": "mesh", "file": "broken.glb"})");
  std::string message = ErrorOf(broken.Text(), dir);
  EXPECT_NE(message.find("scenes/bad.json: objects[0].file: "), std::string::npos) << message;
  // The container header is refused before tinygltf parses anything.
  EXPECT_NE(message.find("broken.glb\": GLB container version"), std::string::npos) << message;
}

TEST(SceneErrors, MissingOrMalformedSceneFile) {
  std::string missing = test::TempDir() + "/absent.json";
  try {
    LoadScene(missing);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(missing + ": "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
  Parts trailingComma;
  trailingComma.render += ",";
  ExpectError(trailingComma, "malformed JSON near render", "line 1");
  EXPECT_NE(ErrorOf("").find("scenes/bad.json: malformed JSON"), std::string::npos);
  EXPECT_NE(ErrorOf("[1, 2]").find("scenes/bad.json: expected an object, got array"),
            std::string::npos) << ErrorOf("[1, 2]");
}

// Rough conductors and dielectrics and plastic (smooth and rough) render now: they load with
// the fields as written, and their fields are still checked.
TEST(SceneErrors, RoughAndPlasticMaterialsLoad) {
  struct Case {
    const char* json;
    MaterialType type;
    float roughness;
  };
  const Case cases[] = {
      {R"({"type": "plastic", "albedo": [0.8, 0.1, 0.1], "ior": 1.5})", MaterialType::kPlastic, 0.0f},
      {R"({"type": "plastic", "albedo": [0.8, 0.1, 0.1], "ior": 1.5, "roughness": 0.3})",
       MaterialType::kPlastic, 0.3f},
      {R"({"type": "conductor", "albedo": [1, 1, 1], "roughness": 0.2})", MaterialType::kConductor,
       0.2f},
      {R"({"type": "dielectric", "ior": 1.5, "roughness": 0.1})", MaterialType::kDielectric, 0.1f},
  };
  for (const Case& c : cases) {
    SceneDesc s = LoadSceneFromString(WithMaterial(c.json).Text(), "scenes/ok.json",
                                      test::SourcePath("scenes"));
    ASSERT_EQ(s.materials.size(), 1u) << c.json;
    EXPECT_EQ(s.materials[0].type, c.type) << c.json;
    EXPECT_EQ(s.materials[0].roughness, c.roughness) << c.json;
  }
  SceneDesc plastic = LoadSceneFromString(WithMaterial(cases[1].json).Text(), "scenes/ok.json",
                                          test::SourcePath("scenes"));
  EXPECT_EQ(plastic.materials[0].albedo, vec3(0.8f, 0.1f, 0.1f));
  EXPECT_EQ(plastic.materials[0].ior, 1.5f);
  // Their fields are still checked: a bad field of a plastic is reported as such.
  ExpectError(WithMaterial(R"({"type": "plastic", "albedo": [2, 0, 0], "ior": 1.5})"),
              "materials.m.albedo[0]", "outside [0, 1]");
  ExpectError(WithMaterial(R"({"type": "plastic", "albedo": [0.5, 0.5, 0.5]})"),
              "materials.m.ior", "missing required field");
  ExpectError(WithMaterial(R"({"type": "dielectric", "ior": 1.5, "roughness": 1.2})"),
              "materials.m.roughness", "outside [0, 1]");
}

}  // namespace
}  // namespace pt
