// A glTF file as the whole scene: its cameras (node transforms, selection by index or name,
// refusals that list what exists), the render defaults, the automatic camera's framing rule,
// the default environment of an unlit file and the one summary line per file.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <random>

#include "src/io/scene_loader.h"
#include "src/scene/auto_camera.h"
#include "tests/gltf_scene_writer.h"
#include "tests/test_util.h"

namespace pt {
namespace {

using GltfJson = test::GltfSceneWriter::Json;

using test::kDeg;

// Where a world point lands in normalised image coordinates ([-1, 1] inside); false behind.
bool Project(const Camera& c, vec3 p, vec2* ndc) {
  vec3 d = p - c.position;
  float z = glm::dot(d, c.forward);
  if (!(z > 0.0f)) return false;
  *ndc = vec2(glm::dot(d, c.right) / (z * c.tanHalfFovY * c.aspect),
              glm::dot(d, c.up) / (z * c.tanHalfFovY));
  return true;
}

glm::dmat4 RootMatrix() {  // T * R * S of the root node below, computed by glm
  return glm::translate(glm::dmat4(1.0), glm::dvec3(1, 2, 3)) *
         glm::rotate(glm::dmat4(1.0), 90.0 * kDeg, glm::dvec3(0, 1, 0)) *
         glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
}
glm::dmat4 MainMatrix() {
  return glm::translate(glm::dmat4(1.0), glm::dvec3(0, 1, 4)) *
         glm::rotate(glm::dmat4(1.0), 10.0 * kDeg, glm::dvec3(0, 1, 0));
}
glm::dmat4 SideMatrix() {
  return glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 5)) *
         glm::rotate(glm::dmat4(1.0), -20.0 * kDeg, glm::dvec3(1, 0, 0));
}

// Cameras 0 "Main" (a node matrix, aspect 2), 1 "Side" (TRS, placed first in the walk),
// 2 "Ortho" (orthographic), 3 "Unplaced" (no node places it); all under a rotated, scaled and
// moved root with the floor.
std::string WriteCameraScene(const std::string& dir) {
  test::GltfSceneWriter w;
  w.AddCamera(test::GltfSceneWriter::Perspective(0.7, 2.0, "Main"));
  w.AddCamera(test::GltfSceneWriter::Perspective(0.5, 0.0, "Side"));
  w.AddCamera({{"type", "orthographic"}, {"name", "Ortho"},
               {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}});
  w.AddCamera(test::GltfSceneWriter::Perspective(0.6, 0.0, "Unplaced"));
  int floor = w.AddFloor(1.0f);
  glm::dmat4 main = MainMatrix();
  GltfJson matrix = GltfJson::array();
  for (int i = 0; i < 16; ++i) matrix.push_back(main[i / 4][i % 4]);  // column-major
  int side = w.AddNode({{"name", "SideNode"}, {"camera", 1}, {"translation", {0, 0, 5}},
                        {"rotation", test::GltfRotation(-20, {1, 0, 0})}}, false);
  int mainNode = w.AddNode({{"name", "MainNode"}, {"camera", 0}, {"matrix", matrix}}, false);
  int ortho = w.AddNode({{"name", "OrthoNode"}, {"camera", 2}, {"translation", {0, 0, 3}}}, false);
  int mesh = w.AddNode({{"mesh", floor}}, false);
  w.AddNode({{"translation", {1, 2, 3}}, {"rotation", test::GltfRotation(90, {0, 1, 0})},
             {"scale", {2, 2, 2}}, {"children", {side, mainNode, ortho, mesh}}});
  return w.Write(dir, "cameras");
}

void ExpectCameraAt(const Scene& scene, const glm::dmat4& world, double fovRadians) {
  glm::dvec3 position(world[3]);
  glm::dvec3 forward = glm::normalize(glm::dvec3(world * glm::dvec4(0, 0, -1, 0)));
  glm::dvec3 up = glm::normalize(glm::dvec3(world * glm::dvec4(0, 1, 0, 0)));
  const Camera& c = scene.camera;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(c.position[k], position[k], 1e-5 * glm::length(position)) << "axis " << k;
    EXPECT_NEAR(c.forward[k], forward[k], 1e-6) << "axis " << k;
    EXPECT_NEAR(c.up[k], up[k], 1e-6) << "axis " << k;
  }
  EXPECT_NEAR(c.tanHalfFovY, std::tan(0.5 * fovRadians), 1e-6);
}

TEST(GltfScene, FirstPerspectiveCameraWithItsNodeTransform) {
  std::string path = WriteCameraScene(test::TempDir());
  Scene scene = BuildScene(LoadScene(path));
  // Camera 0 (the lowest index) though the walk meets camera 1 first.
  ExpectCameraAt(scene, RootMatrix() * MainMatrix(), 0.7);
  EXPECT_EQ(scene.desc.render.width, 1440);  // 720 x aspectRatio 2
  EXPECT_EQ(scene.desc.render.height, 720);
  EXPECT_FLOAT_EQ(scene.desc.render.aspect, 2.0f);
  EXPECT_EQ(scene.desc.render.spp, 64);
  EXPECT_EQ(scene.desc.render.maxDepth, 12);
}

TEST(GltfScene, CameraSelectedByIndexCameraNameOrNodeName) {
  std::string path = WriteCameraScene(test::TempDir());
  for (const char* selector : {"1", "Side", "SideNode"}) {
    SCOPED_TRACE(selector);
    Scene scene = BuildScene(LoadScene(path, LoadOptions{selector}));
    ExpectCameraAt(scene, RootMatrix() * SideMatrix(), 0.5);
    EXPECT_EQ(scene.desc.render.width, 1280);  // no aspectRatio: 16:9
    EXPECT_EQ(scene.desc.render.height, 720);
  }
  ExpectCameraAt(BuildScene(LoadScene(path, LoadOptions{"MainNode"})), RootMatrix() * MainMatrix(),
                 0.7);
}

TEST(GltfScene, UnknownUnplacedOrOrthographicCameraIsAnErrorListingTheCameras) {
  std::string path = WriteCameraScene(test::TempDir());
  const std::string list = "0 \"Main\" (node \"MainNode\"), 1 \"Side\" (node \"SideNode\"), "
                           "2 \"Ortho\" (node \"OrthoNode\") [orthographic]";
  struct Case {
    const char* selector;
    std::string phrase;
  };
  for (const Case& c : {Case{"Nope", "no camera \"Nope\" placed in the default scene"},
                        Case{"3", "no camera 3 placed in the default scene"},
                        Case{"17", "no camera 17"},
                        Case{"Ortho", "camera \"Ortho\" is orthographic"}}) {
    try {
      LoadScene(path, LoadOptions{c.selector});
      ADD_FAILURE() << c.selector << " was accepted";
    } catch (const SceneError& e) {
      std::string m = e.what();
      EXPECT_EQ(m.rfind(path + ": --camera: ", 0), 0u) << m;
      EXPECT_NE(m.find(c.phrase), std::string::npos) << m;
      EXPECT_NE(m.find(list), std::string::npos) << m;
    }
  }
}

// Every corner of many boxes (of any scale and flatness), for several aspect ratios and fields
// of view, projects inside the image; the camera looks along -Z from the rule's distance, and
// the framing is tight (the widest corner reaches 1 / margin of the way to the edge, unless the
// bounding-sphere floor of the rule applies).
TEST(AutoCamera, EveryCornerOfTheBoundsProjectsInsideTheImage) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int trial = 0; trial < 300; ++trial) {
    float scale = std::pow(10.0f, 3.0f * unit(rng));
    vec3 center = scale * 10.0f * vec3(unit(rng), unit(rng), unit(rng));
    vec3 extent = scale * glm::abs(vec3(unit(rng), unit(rng), unit(rng)));
    if (trial % 5 == 0) extent[trial % 3] = 0.0f;  // flat boxes (a floor, a wall)
    bool cube = trial % 7 == 0;
    if (cube) extent = vec3(scale);
    float aspect = std::array<float, 3>{0.3f, 1.0f, 2.4f}[trial % 3];
    float fov = std::array<float, 3>{20.0f, 40.0f, 90.0f}[(trial / 3) % 3];
    CameraDesc desc = FrameBounds(center - extent, center + extent, aspect, fov);
    Camera cam = MakeCamera(desc, int(aspect * 1000), 1000);
    float reach = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
      vec3 p = center + vec3(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1) * extent;
      vec2 ndc;
      ASSERT_TRUE(Project(cam, p, &ndc)) << "trial " << trial << " corner behind the camera";
      EXPECT_LE(std::abs(ndc.x), 1.0f) << "trial " << trial << " corner " << corner;
      EXPECT_LE(std::abs(ndc.y), 1.0f) << "trial " << trial << " corner " << corner;
      reach = std::max(reach, std::max(std::abs(ndc.x), std::abs(ndc.y)));
    }
    double tanY = std::tan(0.5 * fov * kDeg), tanX = tanY * aspect;
    glm::dvec3 h(extent);
    double tight = h.z + 1.1 * std::max(h.x / tanX, h.y / tanY);
    if (tight >= 1.1 * glm::length(h)) {
      EXPECT_NEAR(reach, 1.0f / 1.1f, 1e-3) << "trial " << trial;
    }
    if (cube) {
      EXPECT_GE(reach, 0.5f) << "trial " << trial;
    }
    glm::dvec3 offset = glm::dvec3(desc.position) - glm::dvec3(center);
    double distance = std::max(tight, 1.1 * glm::length(h));
    if (glm::length(h) > 0.0) {
      EXPECT_NEAR(offset.z, distance, 1e-5 * distance) << "trial " << trial;
      EXPECT_NEAR(offset.x, 0.0, 1e-5 * distance) << "trial " << trial;
      EXPECT_NEAR(offset.y, 0.0, 1e-5 * distance) << "trial " << trial;
    }
  }
}

// A file without a camera: the automatic camera looks at the bounds' centre from the front
// (+Z, along -Z), and the image size (here changed after loading, as --width and --height
// do) is the one it frames for.
TEST(AutoCamera, FileWithoutCameraIsFramedFromTheFront) {
  test::GltfSceneWriter w;
  int mesh = w.AddMesh({vec3(-3, 0, -1), vec3(5, 0, -1), vec3(5, 2, 4), vec3(-3, 7, 4)},
                       {0, 1, 2, 0, 2, 3});
  w.AddNode({{"mesh", mesh}});
  SceneDesc desc = LoadScene(w.Write(test::TempDir(), "nocamera", true));
  EXPECT_TRUE(desc.camera.autoFrame);
  EXPECT_EQ(desc.render.width, 1280);
  EXPECT_EQ(desc.render.height, 720);
  for (vec2 size : {vec2(1280, 720), vec2(300, 900)}) {
    SceneDesc d = desc;
    d.render.width = int(size.x);
    d.render.height = int(size.y);
    Scene scene = BuildScene(d);
    vec3 toCamera(0.0f, 0.0f, 1.0f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(scene.camera.forward[k], -toCamera[k], 1e-6);
    vec3 aim = scene.camera.position + scene.camera.forward * glm::length(scene.camera.position - vec3(1, 3.5f, 1.5f));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(aim[k], vec3(1, 3.5f, 1.5f)[k], 1e-4);
    for (const Triangle& t : scene.desc.triangles) {
      for (vec3 p : {t.p0, t.p1, t.p2}) {
        vec2 ndc;
        ASSERT_TRUE(Project(scene.camera, p, &ndc));
        EXPECT_LE(std::max(std::abs(ndc.x), std::abs(ndc.y)), 1.0f);
      }
    }
  }
}

int CountContaining(const std::vector<std::string>& lines, const std::string& phrase) {
  return int(std::count_if(lines.begin(), lines.end(), [&](const std::string& l) {
    return l.find(phrase) != std::string::npos;
  }));
}

// The default environment lights every model file, as viewers do, whatever lights the file
// brings (a point light, an emissive material add to it); said once on the file's line. An
// environment from the command line (--env FILE or --env none) replaces it.
TEST(GltfScene, DefaultEnvironmentLightsEveryFile) {
  std::string dir = test::TempDir();
  auto write = [&](const std::string& name, int lightKind) {
    test::GltfSceneWriter w;
    int material = -1;
    if (lightKind == 2) {
      w.doc["materials"] = {{{"emissiveFactor", {1, 0.5, 0.25}},
                             {"pbrMetallicRoughness", {{"metallicFactor", 0}}}}};
      material = 0;
    }
    w.AddNode({{"mesh", w.AddFloor(1.0f, 0.0f, material)}});
    if (lightKind == 1) {
      w.AddNode(test::GltfSceneWriter::LightNode(
          w.AddLight({{"type", "point"}, {"intensity", 3}}), {{"translation", {0, 1, 0}}}));
    }
    return w.Write(dir, name);
  };
  const std::string phrase = "lit by the default environment, a uniform radiance of 1 from "
                             "every direction";
  const std::string how = " (--env FILE replaces the environment, --env none removes it)";
  std::string unlitPath = write("unlit", 0);
  SceneDesc unlit = LoadScene(unlitPath);
  // With the automatic camera's note, one line for the file.
  ASSERT_EQ(unlit.warnings.size(), 1u);
  EXPECT_EQ(unlit.warnings[0], unlitPath + ": no camera, framed automatically; " + phrase + how);
  EXPECT_EQ(unlit.background, vec3(1.0f));
  const char* own[] = {"", ", and by the file's 1 light", ", and by the file's emissive materials"};
  for (int kind : {1, 2}) {
    SceneDesc lit = LoadScene(write("lit" + std::to_string(kind), kind));
    EXPECT_EQ(CountContaining(lit.warnings, phrase + own[kind] + how), 1) << kind;
    EXPECT_EQ(lit.background, vec3(1.0f)) << kind;
    EXPECT_EQ(lit.pointLights.size(), kind == 1 ? 1u : 0u);
  }
  LoadOptions withEnv;
  withEnv.environmentGiven = true;
  SceneDesc given = LoadScene(unlitPath, withEnv);
  EXPECT_EQ(CountContaining(given.warnings, "default environment"), 0);
  EXPECT_EQ(given.background, vec3(0.0f));
}

// What the renderer ignores of a file is one line, however many objects it concerns.
TEST(GltfScene, IgnoredPartsAreOneSummaryLine) {
  test::GltfSceneWriter w;
  w.AddNode({{"mesh", w.AddFloor(1.0f)}});
  for (int i = 0; i < 3; ++i) {
    int light = w.AddLight({{"type", "point"}, {"range", 5.0 + i}});
    w.AddNode(test::GltfSceneWriter::LightNode(light, {{"translation", {0, 1 + i, 0}}}));
  }
  GltfJson ortho = {{"type", "orthographic"},
                    {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}};
  for (int i = 0; i < 2; ++i) w.AddNode({{"camera", w.AddCamera(ortho)}});
  w.doc["extensionsUsed"].push_back("KHR_xmp");
  w.doc["extensionsUsed"].push_back("KHR_texture_transform");  // read by the materials
  std::string path = w.Write(test::TempDir(), "ignored");
  SceneDesc desc = LoadScene(path);
  ASSERT_EQ(CountContaining(desc.warnings, "ignored:"), 1);
  std::string line;
  for (const std::string& l : desc.warnings) {
    if (l.find("ignored:") != std::string::npos) line = l;
  }
  EXPECT_EQ(line, path + ": no perspective camera, framed automatically; lit by the default "
                         "environment, a uniform radiance of 1 from every direction, and by the "
                         "file's 3 lights (--env FILE replaces the environment, --env none "
                         "removes it); ignored: 2 orthographic "
                         "cameras (unsupported), the range of 3 lights (inverse-square falloff "
                         "everywhere), extension KHR_xmp");
  EXPECT_EQ(desc.pointLights.size(), 3u);
}

TEST(GltfScene, RequiredExtensionsTheRendererCannotReadAreRefused) {
  test::GltfSceneWriter w;
  w.AddNode({{"mesh", w.AddFloor(1.0f)}});
  w.doc["extensionsUsed"] = {"EXT_future_compression"};
  w.doc["extensionsRequired"] = {"EXT_future_compression"};
  // What such a file may hold that the parser fails on (an index accessor without a view, as
  // in a Draco primitive): the extension is named, not the parser's error.
  w.doc["accessors"][1].erase("bufferView");
  std::string path = w.Write(test::TempDir(), "future", true);
  try {
    LoadScene(path);
    FAIL() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": extensionsRequired: the file requires "
                                            "EXT_future_compression, which this renderer "
                                            "cannot read");
  }
}

}  // namespace
}  // namespace pt
