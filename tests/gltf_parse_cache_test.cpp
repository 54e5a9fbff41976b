// The scene loader's glTF parse cache (src/io/gltf_loader.h, issue 28): LoadScene parses each
// glTF file once, prefetched on threads, and shares the parse among the file's placements. A
// scene loaded through it must equal the same scene loaded without it (LoadSceneFromString
// parses each placement on its own): a posed placement (an animation at a time) must not pose
// the file's other, static placements, and errors must read as before.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "src/io/scene_loader.h"
#include "src/scene/scene.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// translated.gltf: one triangle placed by two nodes (an instanced mesh), the first moved by
// the LINEAR animation "move" from (0,0,0) to (2,0,0) over t = 0..1.
void WriteParseCacheModels(const std::string& dir) {
  test::GltfSceneWriter w;
  const int mesh = w.AddMesh({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)}, {0, 1, 2});
  const int moved = w.AddNode({{"mesh", mesh}});
  w.AddNode({{"mesh", mesh}, {"translation", {0.0, 3.0, 0.0}}});
  const std::vector<float> times = {0, 1}, values = {0, 0, 0, 2, 0, 0};
  const int input = w.AddAccessor(times.data(), times.size(), 4, 5126, "SCALAR");
  w.doc["accessors"][input]["min"] = {0.0};
  w.doc["accessors"][input]["max"] = {1.0};
  const int output = w.AddAccessor(values.data(), 2, 12, 5126, "VEC3");
  w.doc["animations"] = {{{"name", "move"},
                          {"samplers", {{{"input", input}, {"output", output}}}},
                          {"channels", {{{"sampler", 0},
                                         {"target", {{"node", moved}, {"path", "translation"}}}}}}}};
  w.Write(dir, "translated");
  test::GltfSceneWriter floor;
  floor.AddNode({{"mesh", floor.AddFloor(2.0f)}});
  floor.Write(dir, "floor", /*glb=*/true);
}

constexpr const char* kParseCacheScene = R"({
  "render": {"width": 4, "height": 4, "spp": 1, "max_depth": 1},
  "camera": {"position": [0, 2, 9], "look_at": [0, 0, 0], "fov_y": 40},
  "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "objects": [
    {"type": "mesh", "file": "floor.glb", "material": "white"},
    {"type": "mesh", "file": "translated.gltf", "animation": "move", "time": 0.25},
    {"type": "mesh", "file": "floor.glb", "transform": {"translate": [0, 1, 0]}},
    {"type": "mesh", "file": "translated.gltf"},
    {"type": "mesh", "file": "floor.glb", "transform": {"scale": 0.5}}
  ]})";

void ExpectSameScene(const SceneDesc& a, const SceneDesc& b) {
  EXPECT_TRUE(test::BitIdentical(a.triangles, b.triangles));
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) {
    EXPECT_EQ(a.instances[i].toWorld, b.instances[i].toWorld) << "instance " << i;
    EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh) << "instance " << i;
  }
  EXPECT_EQ(a.warnings, b.warnings);
}

TEST(GltfParseCache, ASceneLoadedThroughItEqualsOneParsedPerPlacement) {
  const std::string dir = test::TempDir();
  WriteParseCacheModels(dir);
  const std::string path = test::WriteText(dir + "/scene.json", kParseCacheScene);
  const SceneDesc cached = LoadScene(path);                                // parses shared
  const SceneDesc each = LoadSceneFromString(kParseCacheScene, path, dir);  // no cache
  ExpectSameScene(cached, each);
  // The posed placement moved its first node by 0.5 in x; the static one did not move.
  ASSERT_EQ(cached.instances.size(), 4u);
  EXPECT_FLOAT_EQ(float(cached.instances[0].toWorld[3].x), 0.5f);
  EXPECT_FLOAT_EQ(float(cached.instances[2].toWorld[3].x), 0.0f);
  EXPECT_FLOAT_EQ(float(cached.instances[3].toWorld[3].y), 3.0f);
  EXPECT_GE(cached.triangles.size(), 6u);  // three floors of two, and the meshes
}

// A broken file and a missing one: the same message (naming the scene's field) either way.
TEST(GltfParseCache, ErrorsReadAsWithoutIt) {
  const std::string dir = test::TempDir();
  WriteParseCacheModels(dir);
  test::WriteText(dir + "/broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  for (const char* file : {"broken.gltf", "missing.glb"}) {
    nlohmann::json scene = nlohmann::json::parse(kParseCacheScene);
    scene["objects"][3]["file"] = file;
    const std::string text = scene.dump();
    const std::string path = test::WriteText(dir + "/scene.json", text);
    std::string viaCache, without;
    try {
      LoadScene(path);
    } catch (const SceneError& e) {
      viaCache = e.what();
    }
    try {
      LoadSceneFromString(text, path, dir);
    } catch (const SceneError& e) {
      without = e.what();
    }
    EXPECT_FALSE(viaCache.empty()) << file;
    EXPECT_EQ(viaCache, without) << file;
    EXPECT_NE(viaCache.find("objects[3]"), std::string::npos) << viaCache;
  }
}

}  // namespace
}  // namespace pt
