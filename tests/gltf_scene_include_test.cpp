// A JSON scene that includes a glTF as an object and overrides its parts: the camera taken
// from the file (by name or index, moved by a transform, or picked by --camera), the file's
// lights kept beside the scene's or left out, its materials replaced by the scene's. The
// included file brings no default environment and no automatic camera (those are for a glTF
// given as the whole scene).
#include <gtest/gtest.h>

#include "src/io/gltf_loader.h"
#include "src/io/scene_loader.h"
#include "tests/gltf_scene_writer.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// dir/model.gltf: the floor (a red file material), cameras "Front" and "Top", a point light.
std::string WriteIncludedModel(const std::string& dir) {
  test::GltfSceneWriter w;
  w.doc["materials"] = {{{"name", "red"}, {"pbrMetallicRoughness",
                                           {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 0}}}}};
  w.AddCamera(test::GltfSceneWriter::Perspective(0.8, 0.0, "Front"));
  w.AddCamera(test::GltfSceneWriter::Perspective(0.4, 0.0, "Top"));
  w.AddNode({{"mesh", w.AddFloor(1.0f, 0.0f, 0)}});
  w.AddNode({{"camera", 0}, {"translation", {0, 1, 4}}});
  w.AddNode({{"camera", 1}, {"translation", {0, 6, 0}}, {"rotation", {-0.7071068, 0, 0, 0.7071068}}});
  w.AddNode(test::GltfSceneWriter::LightNode(
      w.AddLight({{"type", "point"}, {"intensity", 5}}), {{"translation", {0, 2, 0}}}));
  return w.Write(dir, "model");
}

SceneDesc LoadAt(const std::string& dir, const std::string& camera, const std::string& object,
                 const std::string& cameraOption = "") {
  std::string text = R"({"render": {"width": 8, "height": 8, "spp": 1, "max_depth": 2},
      "camera": )" + camera + R"(, "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [)" + object + R"(], "lights": [{"type": "point", "position": [0, 3, 0], "intensity": [1, 1, 1]}]})";
  LoadOptions options;
  options.camera = cameraOption;
  return LoadSceneFromString(text, "include.json", dir, options);
}

const char* kModel = R"({"type": "mesh", "file": "model.gltf"})";

void ExpectSameCamera(const CameraDesc& a, const CameraDesc& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.lookAt, b.lookAt);
  EXPECT_EQ(a.up, b.up);
  EXPECT_FLOAT_EQ(a.fovY, b.fovY);
}

TEST(GltfSceneInclude, CameraFromTheFileByNameIndexOrCameraOption) {
  std::string dir = test::TempDir();
  GltfSceneContents parts = ReadGltfSceneParts(WriteIncludedModel(dir));
  ASSERT_EQ(parts.cameras.size(), 2u);
  ExpectSameCamera(LoadAt(dir, R"({"from_file": "model.gltf"})", kModel).camera, parts.cameras[0].desc);
  ExpectSameCamera(LoadAt(dir, R"({"from_file": "model.gltf", "name": "Top"})", kModel).camera,
                   parts.cameras[1].desc);
  ExpectSameCamera(LoadAt(dir, R"({"from_file": "model.gltf", "index": 1})", kModel).camera,
                   parts.cameras[1].desc);
  // --camera overrides the scene's choice.
  ExpectSameCamera(LoadAt(dir, R"({"from_file": "model.gltf", "name": "Top"})", kModel, "Front").camera,
                   parts.cameras[0].desc);
  EXPECT_FLOAT_EQ(LoadAt(dir, R"({"from_file": "model.gltf", "fov_y": 25})", kModel).camera.fovY, 25.0f);
}

TEST(GltfSceneInclude, CameraFromTheFileMovedByATransform) {
  std::string dir = test::TempDir();
  GltfSceneContents parts = ReadGltfSceneParts(WriteIncludedModel(dir));
  CameraDesc moved = LoadAt(dir, R"({"from_file": "model.gltf", "transform": {"translate": [2, 0, 0]}})",
                            kModel).camera;
  const CameraDesc& front = parts.cameras[0].desc;
  EXPECT_NEAR(moved.position.x, front.position.x + 2.0f, 1e-6f);
  EXPECT_NEAR(moved.position.y, front.position.y, 1e-6f);
  vec3 a = glm::normalize(moved.lookAt - moved.position), b = glm::normalize(front.lookAt - front.position);
  EXPECT_NEAR(glm::dot(a, b), 1.0f, 1e-6f);
}

TEST(GltfSceneInclude, UnknownCameraOfTheFileNamesTheFieldAndListsTheCameras) {
  std::string dir = test::TempDir();
  WriteIncludedModel(dir);
  for (const auto& [camera, field] :
       {std::pair<std::string, std::string>{R"({"from_file": "model.gltf", "name": "Back"})", "camera.from_file: "},
        {R"({"from_file": "model.gltf", "index": 7})", "camera.from_file: "},
        {R"({"from_file": "absent.gltf"})", "camera.from_file: "}}) {
    try {
      LoadAt(dir, camera, kModel);
      ADD_FAILURE() << camera << " was accepted";
    } catch (const SceneError& e) {
      std::string m = e.what();
      EXPECT_EQ(m.rfind("include.json: " + field, 0), 0u) << m;
      if (camera.find("model.gltf") != std::string::npos) {
        EXPECT_NE(m.find("0 \"Front\""), std::string::npos) << m;
      }
    }
  }
}

TEST(GltfSceneInclude, FileLightsAndMaterialsKeptOrReplaced) {
  std::string dir = test::TempDir();
  WriteIncludedModel(dir);
  const char* camera = R"({"position": [0, 1, 4], "look_at": [0, 0, 0], "fov_y": 40})";
  SceneDesc kept = LoadAt(dir, camera, kModel);
  EXPECT_EQ(kept.pointLights.size(), 2u);  // the scene's and the file's
  ASSERT_FALSE(kept.triangleMaterials.empty());
  EXPECT_EQ(kept.materials[kept.triangleMaterials[0]].albedo, vec3(1, 0, 0));
  SceneDesc replaced = LoadAt(dir, camera,
                            R"({"type": "mesh", "file": "model.gltf", "material": "grey",
                                "lights_from_file": false})");
  EXPECT_EQ(replaced.pointLights.size(), 1u);
  for (uint32_t m : replaced.triangleMaterials) EXPECT_EQ(replaced.materials[m].albedo, vec3(0.5f));
  // A JSON scene's own rules: no automatic camera, no default environment.
  EXPECT_FALSE(kept.camera.autoFrame);
  EXPECT_EQ(kept.background, vec3(0.0f));
}

}  // namespace
}  // namespace pt
