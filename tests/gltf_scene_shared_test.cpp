// The shared Khronos sample models and the Breakfast Room (../shared/assets; skipped in a
// user's clone): each renders from one command with no error at a small size, and the Duck and
// the Breakfast Room are framed by their own cameras.
#include <gtest/gtest.h>

#include <filesystem>

#include "src/io/gltf_loader.h"
#include "src/io/scene_loader.h"
#include "src/scene/scene.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

// Every .glb and .gltf under assets/khronos, and the Breakfast Room.
std::vector<std::string> SharedModels() {
  std::vector<std::string> models;
  for (const auto& entry : fs::recursive_directory_iterator(test::SharedPath("assets/khronos"))) {
    std::string ext = entry.path().extension().string();
    if (ext == ".glb" || ext == ".gltf") models.push_back(entry.path().string());
  }
  std::sort(models.begin(), models.end());
  models.push_back(test::SharedPath("assets/dining-room-bitterli/dining-room.glb"));
  return models;
}

TEST(GltfSceneShared, EveryModelRendersFromOneCommand) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  std::string dir = test::TempDir();
  std::vector<std::string> models = SharedModels();
  EXPECT_GE(models.size(), 9u);
  for (const std::string& model : models) {
    std::string out = dir + "/" + fs::path(model).stem().string() + ".png";
    std::string output;
    int status = test::RunCommand(test::BinaryPath("pathtracer") + " '" + model + "' -o " + out +
                                      " --width 24 --height 24 --spp 1 --quiet",
                                  &output);
    EXPECT_EQ(status, 0) << model << ": " << output;
    EXPECT_TRUE(fs::is_regular_file(out)) << model;
    EXPECT_EQ(output.find("error"), std::string::npos) << model << ": " << output;
  }
}

// Where a world point lands in normalised image coordinates ([-1, 1] inside); false behind.
bool InView(const Camera& c, vec3 p) {
  vec3 d = p - c.position;
  float z = glm::dot(d, c.forward);
  if (!(z > 0.0f)) return false;
  return std::abs(glm::dot(d, c.right) / (z * c.tanHalfFovY * c.aspect)) <= 1.0f &&
         std::abs(glm::dot(d, c.up) / (z * c.tanHalfFovY)) <= 1.0f;
}

// The scene's camera is the file's first camera (not the automatic one), and it sees the model:
// at least `minFraction` of the triangles' centroids project inside the image.
void ExpectFramedByItsOwnCamera(const std::string& relative, double minFraction) {
  std::string path = test::SharedPath(relative);
  SceneDesc desc = LoadScene(path);
  EXPECT_FALSE(desc.camera.autoFrame) << path;
  GltfSceneContents parts = ReadGltfSceneParts(path);
  ASSERT_FALSE(parts.cameras.empty()) << path;
  EXPECT_EQ(desc.camera.position, parts.cameras[0].desc.position);
  EXPECT_EQ(desc.camera.lookAt, parts.cameras[0].desc.lookAt);
  for (const std::string& w : desc.warnings)
    EXPECT_EQ(w.find("framed automatically"), std::string::npos) << w;
  Scene scene = BuildScene(std::move(desc));
  size_t seen = 0;
  for (const Triangle& t : scene.desc.triangles) seen += InView(scene.camera, (t.p0 + t.p1 + t.p2) / 3.0f);
  EXPECT_GE(double(seen), minFraction * double(scene.desc.triangles.size()))
      << path << ": " << seen << " of " << scene.desc.triangles.size() << " triangles in view";
}

TEST(GltfSceneShared, DuckAndBreakfastRoomAreFramedByTheirOwnCameras) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  ExpectFramedByItsOwnCamera("assets/khronos/Duck/glTF-Binary/Duck.glb", 0.95);
  // Inside the room: the camera sees a part of it (what is behind it is the rest).
  ExpectFramedByItsOwnCamera("assets/dining-room-bitterli/dining-room.glb", 0.2);
}

}  // namespace
}  // namespace pt
