// glTF corner cases on a hand-written .gltf + .bin: strips, fans, non-indexed and sparse
// accessors, uint8 indices, a column-major node matrix, a mirroring node, line primitives.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "src/io/scene_loader.h"
#include "src/scene/instances.h"
#include "tests/test_util.h"

namespace pt {
namespace {

// Writes the model into dir/m.gltf and dir/m.bin.
void WriteModel(const std::string& dir) {
  std::vector<char> bin;
  const float positions[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};  // a unit square's corners
  const uint8_t strip[4] = {0, 1, 2, 3}, fan[4] = {0, 1, 3, 2}, sparseIndex[4] = {2, 0, 0, 0};
  const float sparseValue[3] = {0, 5, 0};
  test::AppendRaw(bin, positions, 48);
  test::AppendRaw(bin, strip, 4);
  test::AppendRaw(bin, fan, 4);
  test::AppendRaw(bin, sparseIndex, 4);
  test::AppendRaw(bin, sparseValue, 12);
  std::ofstream(dir + "/m.bin", std::ios::binary).write(bin.data(), std::streamsize(bin.size()));
  std::ofstream(dir + "/m.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1], "children": [1, 2]},
              {"mesh": 0}, {"mesh": 0, "scale": [-1, 1, 1]}],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "indices": 1, "mode": 5},
      {"attributes": {"POSITION": 0}, "indices": 2, "mode": 6},
      {"attributes": {"POSITION": 3}},
      {"attributes": {"POSITION": 0}, "mode": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5121, "count": 4, "type": "SCALAR"},
      {"bufferView": 2, "componentType": 5121, "count": 4, "type": "SCALAR"},
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [0, 0, 0], "max": [1, 5, 0],
       "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5121},
                  "values": {"bufferView": 4}}}],
    "bufferViews": [
      {"buffer": 0, "byteOffset": 0, "byteLength": 48},
      {"buffer": 0, "byteOffset": 48, "byteLength": 4},
      {"buffer": 0, "byteOffset": 52, "byteLength": 4},
      {"buffer": 0, "byteOffset": 56, "byteLength": 1},
      {"buffer": 0, "byteOffset": 60, "byteLength": 12}],
    "buffers": [{"uri": "m.bin", "byteLength": 72}]})";
}

TEST(SceneGltf, StripsFansSparseAndNodeTransforms) {
  std::string dir = test::TempDir();
  WriteModel(dir);
  std::string text = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40},
      "materials": {}, "objects": [{"type": "mesh", "file": "m.gltf"}]})";
  SceneDesc loaded = LoadSceneFromString(text, "gltf.json", dir);
  // Two nodes share the mesh: it is stored once (strip 2 + fan 2 + non-indexed 1; the lines
  // primitive is skipped) and placed twice.
  ASSERT_EQ(loaded.meshes.size(), 1u);
  ASSERT_EQ(loaded.instances.size(), 2u);
  EXPECT_EQ(loaded.meshes[0].triangleCount, 5u);
  EXPECT_EQ(loaded.triangles.size(), 5u);
  SceneDesc s = FlattenInstances(loaded);
  ASSERT_EQ(s.triangles.size(), 10u);
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const Triangle& t = s.triangles[i];
    bool mirrored = i >= 5;  // the second instance, scaled by -1 in x, then moved by +10
    vec3 n = glm::normalize(glm::cross(t.p1 - t.p0, t.p2 - t.p0));
    // glTF: a negative determinant makes clockwise faces front ones, so the front stays +z.
    EXPECT_NEAR(n.z, 1.0f, 1e-6f) << "triangle " << i;
    for (vec3 p : {t.p0, t.p1, t.p2}) {
      EXPECT_GE(p.x, mirrored ? 9.0f : 10.0f);
      EXPECT_LE(p.x, mirrored ? 10.0f : 11.0f);
    }
  }
  EXPECT_EQ(s.triangles[4].p2, vec3(10, 5, 0));  // the sparse substitution of vertex 2
  int lineWarnings = 0;
  for (const std::string& w : s.warnings) lineWarnings += w.find("lines") != std::string::npos;
  EXPECT_EQ(lineWarnings, 1);
  // No material on the primitives: the glTF default (metallic 1, roughness 1) with a warning.
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].type, MaterialType::kConductor);
  EXPECT_EQ(s.materialNames[0], "m.gltf:default");
}

TEST(SceneGltf, MalformedIndexIsAnError) {
  std::string dir = test::TempDir();
  WriteModel(dir);
  std::ofstream(dir + "/m.bin", std::ios::binary | std::ios::in | std::ios::out)
      .seekp(48).put(char(9));  // strip index 9 of 4 vertices
  std::string text = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40},
      "materials": {}, "objects": [{"type": "mesh", "file": "m.gltf"}]})";
  try {
    LoadSceneFromString(text, "gltf.json", dir);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("gltf.json: objects[0].file: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pt
