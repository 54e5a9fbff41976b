// glTF texture coordinates and base colour textures through the scene loader: a hand-written
// .gltf (float, normalized unsigned byte and short TEXCOORD_0, an external PNG, samplers, an
// undecodable image: ignored where no used material needs it, an error where one does) and
// the Khronos Duck.
#include <gtest/gtest.h>

#include <fstream>

#include "src/io/gltf_loader.h"
#include "src/io/scene_loader.h"
#include "tests/test_util.h"
#include "tests/texture_test_util.h"

namespace pt {
namespace {

// The 2 x 2 image's 8-bit codes (RGBA; alpha must be ignored), rows top to bottom.
const uint8_t kTexels[4][4] = {{255, 0, 0, 10}, {0, 255, 0, 255}, {0, 0, 255, 128}, {128, 64, 32, 255}};

// dir/m.gltf + m.bin + tex.png. Primitives in order: B (1 triangle, no UVs, material
// `firstMaterial`), A (the square, float UVs, "checker"), C (ubyte UVs, "metal"), D (ushort
// UVs, "second-set"), E (no UVs, "checker").
void WriteModel(const std::string& dir, int firstMaterial = 1) {
  const float positions[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const float uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};
  const uint8_t indices[8] = {0, 1, 2, 0, 2, 3, 0, 0};  // 2 bytes of padding
  const uint8_t uvBytes[12] = {0, 0, 0, 0, 255, 128, 0, 0, 51, 255, 0, 0};  // stride 4
  const uint16_t uvShorts[6] = {0, 0, 65535, 32768, 13107, 65535};
  std::string bin;
  test::AppendBytes(bin, positions, 12);
  test::AppendBytes(bin, uvs, 8);
  test::AppendBytes(bin, indices, 8);
  test::AppendBytes(bin, uvBytes, 12);
  test::AppendBytes(bin, uvShorts, 6);
  test::WriteFile(dir + "/m.bin", bin);
  test::RgbaImage image(2, 2);
  for (int i = 0; i < 4; ++i) {
    image.Set(i % 2, i / 2, kTexels[i][0], kTexels[i][1], kTexels[i][2], kTexels[i][3]);
  }
  test::WriteFile(dir + "/tex.png", test::EncodePng(image));
  std::ofstream(dir + "/m.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "extensionsUsed": ["KHR_texture_transform"],
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 3}, "material": )" << firstMaterial << R"(},
      {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
      {"attributes": {"POSITION": 3, "TEXCOORD_0": 4}, "material": 3},
      {"attributes": {"POSITION": 3, "TEXCOORD_0": 5}, "material": 4},
      {"attributes": {"POSITION": 3}, "material": 0}]}],
    "materials": [
      {"name": "checker", "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.25,
        "baseColorFactor": [0.5, 1, 1, 1], "baseColorTexture": {"index": 0}}},
      {"name": "plain", "pbrMetallicRoughness": {"roughnessFactor": 0.5,
        "baseColorFactor": [0.9, 0.8, 0.7, 1]}},
      {"name": "unused", "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}}},
      {"name": "metal", "alphaMode": "MASK", "normalTexture": {"index": 0},
       "pbrMetallicRoughness": {"baseColorTexture": {"index": 1,
         "extensions": {"KHR_texture_transform": {"scale": [2, 2]}}}}},
      {"name": "second-set", "pbrMetallicRoughness": {"metallicFactor": 0,
        "baseColorTexture": {"index": 0, "texCoord": 1}}}],
    "textures": [{"source": 0, "sampler": 0}, {"source": 0}, {"source": 1}],
    "samplers": [{"wrapS": 33071, "wrapT": 33648}],
    "images": [{"uri": "tex.png"}, {"uri": "data:image/png;base64,Z2FyYmFnZQ=="}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [-1, -1, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
      {"bufferView": 2, "componentType": 5121, "count": 6, "type": "SCALAR"},
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
       "min": [-1, -1, 0], "max": [1, 1, 0]},
      {"bufferView": 3, "componentType": 5121, "normalized": true, "count": 3, "type": "VEC2"},
      {"bufferView": 4, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC2"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                    {"buffer": 0, "byteOffset": 80, "byteLength": 6},
                    {"buffer": 0, "byteOffset": 88, "byteLength": 12, "byteStride": 4},
                    {"buffer": 0, "byteOffset": 100, "byteLength": 12, "byteStride": 4}],
    "buffers": [{"uri": "m.bin", "byteLength": 112}]})";
}

SceneDesc LoadMeshes(const std::string& dir, const std::string& objects) {
  std::string text = R"({"render": {"width": 1, "height": 1, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov_y": 40},
      "materials": {"grey": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "objects": [)" + objects + "]}";
  return LoadSceneFromString(text, "textures.json", dir);
}

std::string WarningsNaming(const SceneDesc& s, const std::string& text) {
  std::string all;
  for (const std::string& w : s.warnings) {
    if (w.find(text) != std::string::npos) all += w + "\n";
  }
  return all;
}

void ExpectUv(vec2 got, vec2 want) {
  EXPECT_NEAR(got.x, want.x, 1e-7f);
  EXPECT_NEAR(got.y, want.y, 1e-7f);
}

TEST(GltfTextures, HandWrittenModelUvsTexelsSamplersAndMaterials) {
  std::string dir = test::TempDir();
  WriteModel(dir);
  SceneDesc s = LoadMeshes(dir, R"({"type": "mesh", "file": "m.gltf"})");
  ASSERT_EQ(s.triangles.size(), 6u);
  ASSERT_EQ(s.triangleUvs.size(), 6u);
  ExpectUv(s.triangleUvs[0].uv0, vec2(0));  // B has no TEXCOORD_0: zeros
  ExpectUv(s.triangleUvs[0].uv2, vec2(0));
  ExpectUv(s.triangleUvs[1].uv0, vec2(0, 1));  // A: vertices 0, 1, 2 then 0, 2, 3
  ExpectUv(s.triangleUvs[1].uv1, vec2(1, 1));
  ExpectUv(s.triangleUvs[1].uv2, vec2(1, 0));
  ExpectUv(s.triangleUvs[2].uv2, vec2(0, 0));
  ExpectUv(s.triangleUvs[3].uv1, vec2(1, 128.0f / 255.0f));  // C: normalized unsigned byte
  ExpectUv(s.triangleUvs[3].uv2, vec2(0.2f, 1));
  ExpectUv(s.triangleUvs[4].uv1, vec2(1, 32768.0f / 65535.0f));  // D: normalized unsigned short
  ExpectUv(s.triangleUvs[4].uv2, vec2(0.2f, 1));
  ExpectUv(s.triangleUvs[5].uv1, vec2(0));  // E: textured material without UVs, read at (0, 0)

  // One decoded image (the undecodable one belongs to an unused material), linear RGB.
  ASSERT_EQ(s.texels.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(s.texels[i][c], Srgb8ToLinear(kTexels[i][c])) << i << c;
  }
  ASSERT_EQ(s.textures.size(), 2u);  // the clamp/mirror sampler, and a repeat view of the same texels
  const Material& checker = s.materials[s.triangleMaterials[1]];
  ASSERT_EQ(checker.baseColorTexture, 0);
  EXPECT_EQ(s.textures[0].width, 2u);
  EXPECT_EQ(s.textures[0].height, 2u);
  EXPECT_EQ(s.textures[0].wrapS, TextureWrap::kClampToEdge);
  EXPECT_EQ(s.textures[0].wrapT, TextureWrap::kMirroredRepeat);
  EXPECT_EQ(checker.type, MaterialType::kPlastic);
  EXPECT_FLOAT_EQ(checker.ior, 1.5f);
  EXPECT_FLOAT_EQ(checker.roughness, 0.25f);
  EXPECT_EQ(checker.albedo, vec3(0.5f, 1, 1));  // the factor; the texture multiplies at lookup
  const Material& metal = s.materials[s.triangleMaterials[3]];
  ASSERT_EQ(metal.baseColorTexture, 1);
  EXPECT_EQ(s.textures[1].offset, s.textures[0].offset);
  EXPECT_EQ(s.textures[1].wrapS, TextureWrap::kRepeat);
  EXPECT_EQ(s.textures[1].wrapT, TextureWrap::kRepeat);
  EXPECT_EQ(metal.type, MaterialType::kConductor);
  EXPECT_FLOAT_EQ(metal.roughness, 1.0f);
  const Material& plain = s.materials[s.triangleMaterials[0]];
  EXPECT_EQ(plain.type, MaterialType::kConductor);
  EXPECT_FLOAT_EQ(plain.roughness, 0.5f);
  EXPECT_EQ(plain.baseColorTexture, -1);
  EXPECT_EQ(s.materials.size(), 1u + 4u);  // the scene's grey and four: "unused" never added

  // Warnings only for what is not honoured, each naming its material.
  std::string metalWarnings = WarningsNaming(s, "\"metal\"");
  for (const char* what : {"normalTexture", "alphaMode MASK", "KHR_texture_transform"}) {
    EXPECT_NE(metalWarnings.find(what), std::string::npos) << what << " in: " << metalWarnings;
  }
  EXPECT_NE(WarningsNaming(s, "\"second-set\"").find("TEXCOORD_1"), std::string::npos);
  std::string checkerWarnings = WarningsNaming(s, "\"checker\"");
  EXPECT_NE(checkerWarnings.find("without TEXCOORD_0"), std::string::npos) << checkerWarnings;
  EXPECT_EQ(checkerWarnings.find(';'), std::string::npos) << checkerWarnings;  // only that
  EXPECT_EQ(WarningsNaming(s, "\"plain\""), "");
  EXPECT_EQ(WarningsNaming(s, "decoded"), "");
  EXPECT_EQ(s.warnings.size(), 3u);
}

// An image a used material needs and stb cannot decode is bad input: the picture would lose it.
TEST(GltfTextures, UndecodableImageOfAUsedMaterialIsAnErrorNamingFileMaterialAndImage) {
  std::string dir = test::TempDir();
  WriteModel(dir, /*firstMaterial=*/2);
  try {
    LoadMeshes(dir, R"({"type": "mesh", "file": "m.gltf"})");
    ADD_FAILURE() << "the undecodable image was accepted";
  } catch (const SceneError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("m.gltf"), std::string::npos) << m;
    const std::string phrase = "material \"unused\" (#2): image #1 (image/png) cannot be decoded";
    EXPECT_NE(m.find(phrase), std::string::npos) << m;
  }
}

TEST(GltfTextures, OverrideDecodesNothingAndUvsStayParallelWithObj) {
  std::string dir = test::TempDir();
  WriteModel(dir);
  std::ofstream(dir + "/tri.obj") << "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nf 1 2 3\nf 2 4 3\n";
  // OBJ first (no coordinates), then the glTF with the scene's material, then OBJ again.
  SceneDesc s = LoadMeshes(dir, R"({"type": "mesh", "file": "tri.obj"},
      {"type": "mesh", "file": "m.gltf", "material": "grey"}, {"type": "mesh", "file": "tri.obj"})");
  ASSERT_EQ(s.triangles.size(), 2u + 6u + 2u);
  ASSERT_EQ(s.triangleUvs.size(), s.triangles.size());
  for (size_t i : {0u, 1u, 2u, 7u, 8u, 9u}) ExpectUv(s.triangleUvs[i].uv1, vec2(0));
  ExpectUv(s.triangleUvs[3].uv1, vec2(1, 1));
  EXPECT_TRUE(s.textures.empty());
  EXPECT_TRUE(s.texels.empty());
  // No mesh with coordinates: the vector stays empty.
  SceneDesc obj = LoadMeshes(dir, R"({"type": "mesh", "file": "tri.obj"})");
  EXPECT_TRUE(obj.triangleUvs.empty());
}

TEST(GltfTextures, KhronosDuckHasUvsAndItsTexture) {
  if (!test::HaveShared()) GTEST_SKIP() << "../shared is not present (a user's clone)";
  SceneDesc s = LoadMeshes(".", R"({"type": "mesh", "file": ")" +
                                    test::SharedPath("assets/khronos/Duck/glTF-Binary/Duck.glb") +
                                    "\"}");
  EXPECT_EQ(s.triangles.size(), 4212u);
  EXPECT_EQ(s.triangleUvs.size(), s.triangles.size());
  ASSERT_EQ(s.materials.size(), 2u);  // the scene's grey, then the duck's blinn3-fx
  const Material& m = s.materials[s.triangleMaterials[0]];
  EXPECT_NE(s.materialNames[s.triangleMaterials[0]].find(":blinn3-fx"), std::string::npos);
  EXPECT_EQ(m.type, MaterialType::kPlastic);  // metallic 0
  EXPECT_FLOAT_EQ(m.roughness, 1.0f);
  ASSERT_EQ(m.baseColorTexture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 512u);
  EXPECT_EQ(s.textures[0].height, 512u);
  EXPECT_EQ(s.texels.size(), 512u * 512u);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // A yellow duck: the texture's mean is yellow (red and green well above blue).
  glm::dvec3 mean(0.0);
  for (vec3 t : s.texels) mean += glm::dvec3(t);
  mean /= double(s.texels.size());
  EXPECT_GT(mean.r, 2.0 * mean.b);
  EXPECT_GT(mean.g, 2.0 * mean.b);
  for (const TriangleUvs& t : s.triangleUvs) {
    for (vec2 uv : {t.uv0, t.uv1, t.uv2}) {
      ASSERT_TRUE(uv.x >= 0.02f && uv.x <= 0.99f && uv.y >= 0.01f && uv.y <= 0.99f);
    }
  }
}

}  // namespace
}  // namespace pt
