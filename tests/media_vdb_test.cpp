// OpenVDB files as grid media (skipped in builds without OpenVDB, where a grid file is a clear
// error instead): a procedural grid written and read back is the same grid; a scene reading it
// renders bit for bit as the procedural one; a file without the named grid, or whose grid is
// not a float grid, is refused naming file and field. Built outside the unity units: it
// includes OpenVDB's headers.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <tuple>

#include "src/io/scene_loader.h"
#include "src/io/vdb_io.h"
#include "src/media/procedural_volume.h"
#include "tests/cli_test_util.h"
#include "tests/render_test_util.h"

#ifdef PT_HAVE_OPENVDB
#include <openvdb/openvdb.h>
#endif

namespace pt {
namespace {

std::string VdbSceneJson(const std::string& gridSource) {
  return R"({"render": {"width": 12, "height": 12, "spp": 4, "max_depth": 4, "seed": 2},
    "camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "fov_y": 40},
    "background": [1, 1, 1],
    "materials": {},
    "media": {"cloud": {"type": "grid", )" + gridSource + R"(,
      "sigma_a": [0.5, 0.5, 0.5], "sigma_s": [6, 6, 6], "g": 0.5}},
    "objects": [{"type": "volume", "medium": "cloud"}]})";
}

TEST(MediaVdb, WithoutOpenVdbGridFilesAreAClearError) {
  if (VdbSupported()) GTEST_SKIP() << "this build reads .vdb files";
  std::string dir = test::TempDir();
  test::WriteText(dir + "/c.vdb", "not read");
  try {
    LoadSceneFromString(VdbSceneJson(R"("file": "c.vdb")"), "s.json", dir);
    FAIL() << "loaded a grid file without OpenVDB";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("media.cloud.file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("libopenvdb-dev"), std::string::npos) << e.what();
  }
}

TEST(MediaVdb, WrittenGridReadsBackAndRendersAsTheProcedural) {
  if (!VdbSupported()) GTEST_SKIP() << "built without OpenVDB";
  std::string dir = test::TempDir();
  SparseGrid grid = MakeNoiseCloud(24, 4);
  WriteVdbGrid(dir + "/cloud.vdb", "density", grid);
  SparseGrid back = ReadVdbGrid(dir + "/cloud.vdb", "density");
  std::map<std::tuple<int, int, int>, std::vector<float>> bricks;
  for (const SparseGrid::Brick& b : back.bricks)
    bricks[{b.origin.x, b.origin.y, b.origin.z}] = b.values;
  ASSERT_EQ(bricks.size(), grid.bricks.size());
  for (const SparseGrid::Brick& b : grid.bricks) {
    const std::vector<float>& read = bricks[std::make_tuple(b.origin.x, b.origin.y, b.origin.z)];
    EXPECT_EQ(read, b.values);
  }
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_DOUBLE_EQ(back.indexToWorld[i][j], grid.indexToWorld[i][j]);

  Scene fromFile =
      BuildScene(LoadSceneFromString(VdbSceneJson(R"("file": "cloud.vdb")"), "s.json", dir));
  Scene procedural = test::SceneFromJson(
      VdbSceneJson(R"("procedural": {"shape": "cloud", "resolution": 24, "seed": 4})"));
  RenderResult a = test::RenderOnCpu(fromFile), b = test::RenderOnCpu(procedural);
  EXPECT_TRUE(test::SameImage(a.image, b.image));
  EXPECT_GT(a.stats.stages.medium, 0.0);
}

// An emission grid of the file scales the medium's emission: a constant density (1) and a
// constant "temperature" (2) slab glows as Le 2 sigma_a / sigma_t (1 - exp(-sigma_t d)).
TEST(MediaVdb, EmissionGridScalesTheEmission) {
  if (!VdbSupported()) GTEST_SKIP() << "built without OpenVDB";
  std::string dir = test::TempDir();
  const double d = 0.5;
  glm::dmat4 toWorld(1.0 / 8.0);  // index [0, 8] -> the unit cube, centred
  toWorld[3] = glm::dvec4(-0.5, -0.5, -0.5, 1.0);
  SparseGrid density = MakeConstantGrid(glm::ivec3(9), 1.0f, toWorld);
  SparseGrid temperature = MakeConstantGrid(glm::ivec3(9), 2.0f, toWorld);
  WriteVdbGrids(dir + "/glow.vdb", {{"density", &density}, {"temperature", &temperature}});
  std::string json = R"({"render": {"width": 8, "height": 8, "spp": 128, "max_depth": 0},
    "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_y": 1},
    "materials": {},
    "media": {"glow": {"type": "grid", "file": "glow.vdb", "emission_grid": "temperature",
      "sigma_a": [1, 1, 1], "sigma_s": [0.5, 0.5, 0.5], "emission": [1, 0.5, 0.25],
      "transform": {"scale": [200, 200, 0.5], "translate": [0, 0, -0.25]}}},
    "objects": [{"type": "box", "min": [-100, -100, -0.5], "max": [100, 100, 0],
      "material": "interface", "interior": "glow"}]})";
  RenderResult r = test::RenderOnCpu(BuildScene(LoadSceneFromString(json, "s.json", dir)));
  const double le[3] = {1.0, 0.5, 0.25};
  for (int c = 0; c < 3; ++c) {
    test::WindowMean m = test::MeanOverImage(r.image, c);
    double expected = 2.0 * le[c] * (1.0 / 1.5) * (1.0 - std::exp(-1.5 * d));
    EXPECT_NEAR(m.mean, expected, test::kZ1e4 * std::sqrt(m.varianceOfMean)) << "channel " << c;
  }
}

TEST(MediaVdb, MissingOrNonFloatGridsAreRefused) {
  if (!VdbSupported()) GTEST_SKIP() << "built without OpenVDB";
#ifdef PT_HAVE_OPENVDB
  std::string dir = test::TempDir();
  WriteVdbGrid(dir + "/smoke.vdb", "density", MakeSmokeSphere(16, 1));
  auto vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  vectors->setName("velocity");
  vectors->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1.0f, 0.0f, 0.0f));
  openvdb::io::File file(dir + "/velocity.vdb");
  openvdb::GridPtrVec grids{vectors};
  file.write(grids);
  file.close();
  struct Case {
    std::string source, field, detail;
  };
  for (const Case& k :
       {Case{R"("file": "smoke.vdb", "grid": "temperature")", "media.cloud.grid",
             "smoke.vdb\": has no grid \"temperature\" (its grids: \"density\")"},
        Case{R"("file": "velocity.vdb", "grid": "velocity")", "media.cloud.grid",
             "grid \"velocity\" holds vec3s values; a medium's density grid must be a float grid"},
        Case{R"("file": "velocity.vdb")", "media.cloud.file", "has no grid \"density\""}}) {
    std::string message = "(no error)";
    try {
      LoadSceneFromString(VdbSceneJson(k.source), "s.json", dir);
    } catch (const SceneError& e) {
      message = e.what();
    }
    EXPECT_EQ(message.rfind("s.json: ", 0), 0u) << message;
    EXPECT_NE(message.find(k.field), std::string::npos) << message;
    EXPECT_NE(message.find(k.detail), std::string::npos) << message;
  }
  std::string scene = test::WriteText(dir + "/no_grid.json",
                                      VdbSceneJson(R"("file": "smoke.vdb", "grid": "heat")"));
  test::ExpectRefusedWritingNothing(scene, "", dir);
#endif
}

}  // namespace
}  // namespace pt
