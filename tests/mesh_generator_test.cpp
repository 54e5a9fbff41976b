// tools/make_mesh_glb writes the committed scenes/meshes/smooth_shapes.glb byte for byte.
#include <gtest/gtest.h>

#include <filesystem>

#include "src/io/scene_loader.h"
#include "tests/test_util.h"

namespace pt {
namespace {

TEST(MeshGenerator, RegeneratesTheCommittedGlbByteForByte) {
  std::string tool = test::BinaryPath("make_mesh_glb");
  if (!std::filesystem::exists(tool)) GTEST_SKIP() << "make_mesh_glb is not built: " << tool;
  std::string out = test::TempDir() + "/smooth_shapes.glb";
  std::string log;
  ASSERT_EQ(test::RunCommand("'" + tool + "' '" + out + "'", &log), 0) << log;
  std::string generated = test::ReadText(out);
  std::string committed = test::ReadText(test::SourcePath("scenes/meshes/smooth_shapes.glb"));
  ASSERT_FALSE(committed.empty());
  EXPECT_EQ(generated.size(), committed.size());
  EXPECT_TRUE(generated == committed)
      << "regenerate with: make_mesh_glb scenes/meshes/smooth_shapes.glb";
  EXPECT_NE(test::RunCommand("'" + tool + "'", &log), 0) << "no argument must be a usage error";
}

TEST(MeshGenerator, GeneratedGlbLoadsThroughTheSceneLoader) {
  std::string dir = test::TempDir();
  std::filesystem::copy_file(test::SourcePath("scenes/meshes/smooth_shapes.glb"), dir + "/s.glb");
  std::string text = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 1, 4], "look_at": [0, 1, 0], "fov_y": 40},
      "materials": {}, "objects": [{"type": "mesh", "file": "s.glb"}]})";
  SceneDesc s = LoadSceneFromString(text, "gen.json", dir);
  EXPECT_EQ(s.triangles.size(), 2624u);
  EXPECT_EQ(s.skippedDegenerateTriangles, 0);
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materialNames[0], "s.glb:gold");
}

}  // namespace
}  // namespace pt
