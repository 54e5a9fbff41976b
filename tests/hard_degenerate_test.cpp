// Hard geometric cases, part 3: degenerate triangles in OBJ and glTF files are skipped with a
// counted warning and never poison the BVH or the image.
#include <gtest/gtest.h>

#include "tests/hard_geometry_util.h"
#include "tests/test_util.h"

namespace pt {
namespace {

using namespace pt::hard;

// ---- Degenerate triangles in mesh files ----

void CheckBvhFinite(const Scene& scene) {
  ASSERT_FALSE(scene.nodes.empty());
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    const BvhNode& n = scene.nodes[i];
    ASSERT_TRUE(IsFinite(n.boundsMin) && IsFinite(n.boundsMax)) << "node " << i;
    ASSERT_TRUE(n.boundsMin.x <= n.boundsMax.x && n.boundsMin.y <= n.boundsMax.y &&
                n.boundsMin.z <= n.boundsMax.z)
        << "node " << i;
  }
  for (const Triangle& t : scene.desc.triangles)
    ASSERT_TRUE(IsFinite(t.p0) && IsFinite(t.p1) && IsFinite(t.p2));
}

// Renders the scene small and checks the non-finite firewall never fired.
void CheckRendersFinite(const Scene& scene) {
  RenderResult r = test::RenderOnCpu(scene);
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  for (float v : r.image.rgb) ASSERT_TRUE(std::isfinite(v));
  double sum = 0.0;
  for (float v : r.image.rgb) sum += v;
  EXPECT_GT(sum, 0.0);  // the valid triangles are there and lit
}

constexpr const char* kMeshSceneJson = R"({
  "render": {"width": 16, "height": 16, "spp": 4, "max_depth": 3, "seed": 1},
  "camera": {"position": [0.5, 0.5, 4], "look_at": [0.5, 0.5, 0], "fov_y": 40},
  "background": [1, 1, 1],
  "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "objects": [{"type": "mesh", "file": "FILE", "material": "m"}]
})";

std::string SceneFor(const std::string& file) {
  std::string s = kMeshSceneJson;
  s.replace(s.find("FILE"), 4, file);
  return s;
}

// OBJ: zero area (repeated vertex), collinear, all three the same, an exactly collinear sliver
// with large coordinates, overflowing coordinates (1e39 reads as float inf) and mixed +-inf
// (inf - inf = NaN in the edges). tinyobjloader has no syntax for NaN ("nan" reads as 0), so the
// NaN case is in the glTF below. Two good triangles (a unit square) survive.
TEST(HardGeometry, DegenerateObjTrianglesAreSkippedAndCounted) {
  std::string dir = test::TempDir();
  std::ofstream(dir + "/degenerate.obj") << R"(# degenerate faces among good ones
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 3 0 0
v 1e39 0 0
v -1e39 1e39 0
v 100000 100000 100000
v 200000 200000 200000
v 300000 300000 300000
f 1 2 3
f 1 3 4
f 1 2 2
f 1 2 5
f 2 5 6
f 3 3 3
f 1 2 7
f 7 8 3
f 9 10 11
)";
  SceneDesc desc = LoadSceneFromString(SceneFor("degenerate.obj"), "obj-scene.json", dir);
  EXPECT_EQ(desc.skippedDegenerateTriangles, 7);
  EXPECT_EQ(desc.triangles.size(), 2u);
  bool warned = false;
  for (const std::string& w : desc.warnings)
    warned = warned || (w.find("7 degenerate") != std::string::npos &&
                        w.find("degenerate.obj") != std::string::npos);
  EXPECT_TRUE(warned) << "no warning names the count and the file";
  Scene scene = BuildScene(std::move(desc));
  CheckBvhFinite(scene);
  CheckRendersFinite(scene);
}

// glTF: the same kinds plus NaN coordinates, as binary floats, indexed by uint16.
TEST(HardGeometry, DegenerateGltfTrianglesAreSkippedAndCounted) {
  std::string dir = test::TempDir();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float positions[] = {
      0, 0, 0,   1, 0, 0,   1, 1, 0,    0, 1, 0,      // 0-3: a unit square
      2, 0, 0,   3, 0, 0,                             // 4-5: collinear with 0, 1
      nan, 0, 0, 0, nan, 1, 0, 0, nan,                // 6-8: NaN coordinates
      inf, 0, 0, -inf, 1, 0, 0, 0, inf,               // 9-11: infinite coordinates
      3e38f, 0, 0, 0, 3e38f, 0,                       // 12-13: finite, but the area overflows
  };
  const uint16_t indices[] = {0, 1, 2,  0, 2, 3,                  // good
                              0, 1, 1,  0, 1, 4,  1, 4, 5,        // repeated, collinear
                              2, 2, 2,                            // one point
                              0, 1, 6,  6, 7, 8,  2, 3, 7,        // NaN
                              0, 1, 9,  9, 10, 11, 3, 10, 2,      // inf
                              0, 12, 13};                         // overflowing normal
  const int skipped = 11;
  std::vector<char> bin;
  test::AppendRaw(bin, positions, sizeof(positions));
  test::AppendRaw(bin, indices, sizeof(indices));
  while (bin.size() % 4) bin.push_back(0);
  std::ofstream(dir + "/d.bin", std::ios::binary).write(bin.data(), std::streamsize(bin.size()));
  size_t vertexCount = sizeof(positions) / 12, indexCount = sizeof(indices) / 2;
  std::ofstream(dir + "/d.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": )" + std::to_string(vertexCount) +
                                        R"(, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5123, "count": )" + std::to_string(indexCount) +
                                        R"(, "type": "SCALAR"}],
    "bufferViews": [
      {"buffer": 0, "byteOffset": 0, "byteLength": )" + std::to_string(sizeof(positions)) + R"(},
      {"buffer": 0, "byteOffset": )" + std::to_string(sizeof(positions)) +
                                        R"(, "byteLength": )" + std::to_string(sizeof(indices)) +
                                        R"(}],
    "buffers": [{"uri": "d.bin", "byteLength": )" + std::to_string(bin.size()) + R"(}]})";
  SceneDesc desc = LoadSceneFromString(SceneFor("d.gltf"), "gltf-scene.json", dir);
  EXPECT_EQ(desc.skippedDegenerateTriangles, skipped);
  EXPECT_EQ(desc.triangles.size(), 2u);
  bool warned = false;
  for (const std::string& w : desc.warnings)
    warned = warned || (w.find(std::to_string(skipped) + " degenerate") != std::string::npos &&
                        w.find("d.gltf") != std::string::npos);
  EXPECT_TRUE(warned) << "no warning names the count and the file";
  Scene scene = BuildScene(std::move(desc));
  CheckBvhFinite(scene);
  CheckRendersFinite(scene);
}

}  // namespace
}  // namespace pt
