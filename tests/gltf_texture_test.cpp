// glTF texture coordinates and textures through the scene loader: a hand-written .gltf (float
// and normalized unsigned byte TEXCOORD_0, normalized unsigned short TEXCOORD_1, an external
// PNG used as sRGB colour and as linear data, samplers, KHR_texture_transform, an undecodable
// image: ignored where no used material needs it, an error where one does) and the Khronos Duck.
#include <gtest/gtest.h>

#include <fstream>

#include "src/materials/texture.h"
#include "src/materials/texture_pyramid.h"
#include "src/io/scene_loader.h"
#include "tests/test_util.h"
#include "tests/texture_test_util.h"

namespace pt {
namespace {

// The 2 x 2 image's 8-bit codes (RGBA; alpha must be ignored), rows top to bottom.
const uint8_t kTexels[4][4] = {{255, 0, 0, 10}, {0, 255, 0, 255}, {0, 0, 255, 128}, {128, 64, 32, 255}};

// dir/m.gltf + m.bin + tex.png. Primitives in order: B (1 triangle, no UVs, material
// `firstMaterial`), A (the square, float UVs, "checker"), C (ubyte UVs, "metal"), D (ushort
// TEXCOORD_1, "second-set"), E (no UVs, "checker").
void WriteUvModel(const std::string& dir, int firstMaterial = 1) {
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
      {"attributes": {"POSITION": 3, "TEXCOORD_1": 5}, "material": 4},
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

void ExpectUv(vec2 got, vec2 want) {
  EXPECT_NEAR(got.x, want.x, 1e-7f);
  EXPECT_NEAR(got.y, want.y, 1e-7f);
}

TEST(GltfTextures, HandWrittenModelUvsTexelsSamplersAndMaterials) {
  std::string dir = test::TempDir();
  WriteUvModel(dir);
  SceneDesc s = LoadMeshes(dir, R"({"type": "mesh", "file": "m.gltf"})");
  ASSERT_EQ(s.triangles.size(), 6u);
  ASSERT_EQ(s.triangleUvs.size(), 6u);
  ExpectUv(s.triangleUvs[0].uv0, vec2(0));  // B's material reads no texture: zeros
  ExpectUv(s.triangleUvs[0].uv2, vec2(0));
  ExpectUv(s.triangleUvs[1].uv0, vec2(0, 1));  // A: vertices 0, 1, 2 then 0, 2, 3
  ExpectUv(s.triangleUvs[1].uv1, vec2(1, 1));
  ExpectUv(s.triangleUvs[1].uv2, vec2(1, 0));
  ExpectUv(s.triangleUvs[2].uv2, vec2(0, 0));
  ExpectUv(s.triangleUvs[3].uv1, vec2(1, 128.0f / 255.0f));  // C: normalized unsigned byte
  ExpectUv(s.triangleUvs[3].uv2, vec2(0.2f, 1));
  ExpectUv(s.triangleUvs[4].uv1, vec2(0));  // D reads TEXCOORD_1 only
  ExpectUv(s.triangleUvs[5].uv1, vec2(0));  // E: textured material without UVs, read at (0, 0)
  ASSERT_EQ(s.triangleUvs1.size(), 6u);  // only D has (and reads) TEXCOORD_1
  ExpectUv(s.triangleUvs1[4].uv1, vec2(1, 32768.0f / 65535.0f));  // normalized unsigned short
  ExpectUv(s.triangleUvs1[4].uv2, vec2(0.2f, 1));
  ExpectUv(s.triangleUvs1[3].uv1, vec2(0));

  // One image, decoded twice: as sRGB colour (base colour) and as linear data (the normal
  // texture). Each is a 2 x 2 + 1 x 1 pyramid whose level 0 is the PNG's codes, alpha kept.
  ASSERT_EQ(s.texels.size(), 2u * 5u);
  ASSERT_EQ(s.textures.size(), 3u);  // sRGB with the clamp/mirror sampler, its repeat view, linear
  for (int t : {0, 2}) {
    ASSERT_EQ(s.textures[t].levels, 2u);
    for (int i = 0; i < 4; ++i) {
      const uint8_t* c = kTexels[i];
      EXPECT_EQ(s.texels[s.textures[t].offset + i], PackRgba8(c[0], c[1], c[2], c[3])) << t << i;
    }
  }
  EXPECT_EQ(s.textures[0].srgb, 1u);
  EXPECT_EQ(s.textures[2].srgb, 0u);
  EXPECT_EQ(s.textures[1].offset, s.textures[0].offset);
  EXPECT_EQ(s.textures[0].wrapS, TextureWrap::kClampToEdge);
  EXPECT_EQ(s.textures[0].wrapT, TextureWrap::kMirroredRepeat);
  EXPECT_EQ(s.textures[1].wrapS, TextureWrap::kRepeat);
  EXPECT_EQ(s.textures[1].wrapT, TextureWrap::kRepeat);

  const Material& checker = s.materials[s.triangleMaterials[1]];
  EXPECT_EQ(checker.type, MaterialType::kGltfPbr);
  EXPECT_FLOAT_EQ(checker.metallic, 0.0f);
  EXPECT_FLOAT_EQ(checker.roughness, 0.25f);
  EXPECT_FLOAT_EQ(checker.ior, 1.5f);
  EXPECT_EQ(checker.albedo, vec3(0.5f, 1, 1));  // the factor; the texture multiplies at lookup
  ASSERT_GE(checker.baseColorTexture, 0);
  EXPECT_EQ(s.textureRefs[checker.baseColorTexture].texture, 0);
  EXPECT_EQ(checker.flags, uint32_t(kMaterialCullBack | kMaterialThinWalled));  // single-sided
  const Material& metal = s.materials[s.triangleMaterials[3]];
  EXPECT_FLOAT_EQ(metal.metallic, 1.0f);  // the glTF defaults
  EXPECT_FLOAT_EQ(metal.roughness, 1.0f);
  EXPECT_TRUE(metal.flags & kMaterialAlphaMask);
  EXPECT_FLOAT_EQ(metal.alphaCutoff, 0.5f);
  ASSERT_GE(metal.baseColorTexture, 0);
  const TextureRef& scaled = s.textureRefs[metal.baseColorTexture];
  EXPECT_EQ(scaled.texture, 1);
  EXPECT_EQ(scaled.row0, vec3(2, 0, 0));  // KHR_texture_transform scale [2, 2]
  EXPECT_EQ(scaled.row1, vec3(0, 2, 0));
  ASSERT_GE(metal.normalTexture, 0);
  EXPECT_EQ(s.textureRefs[metal.normalTexture].texture, 2);
  const Material& second = s.materials[s.triangleMaterials[4]];
  ASSERT_GE(second.baseColorTexture, 0);
  EXPECT_EQ(s.textureRefs[second.baseColorTexture].texCoord, 1u);
  const Material& plain = s.materials[s.triangleMaterials[0]];
  EXPECT_FLOAT_EQ(plain.metallic, 1.0f);
  EXPECT_FLOAT_EQ(plain.roughness, 0.5f);
  EXPECT_EQ(plain.baseColorTexture, -1);
  EXPECT_EQ(s.materials.size(), 1u + 4u);  // the scene's grey and four: "unused" never added

  // One summary line for the file, naming only what is not honoured, with material counts.
  ASSERT_EQ(s.warnings.size(), 1u) << s.warnings.front();
  const std::string& w = s.warnings[0];
  EXPECT_EQ(w.rfind("m.gltf: materials: ", 0), 0u) << w;
  EXPECT_NE(w.find("textures read at (0, 0) on primitives without TEXCOORD_0 (1 material)"),
            std::string::npos) << w;
  for (const char* honoured : {"normalTexture", "MASK", "KHR_texture_transform", "TEXCOORD_1", "decoded"})
    EXPECT_EQ(w.find(honoured), std::string::npos) << honoured << " in: " << w;
}

// An image a used material needs and stb cannot decode is bad input: the picture would lose it.
TEST(GltfTextures, UndecodableImageOfAUsedMaterialIsAnErrorNamingFileMaterialAndImage) {
  std::string dir = test::TempDir();
  WriteUvModel(dir, /*firstMaterial=*/2);
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

TEST(GltfTextures, OverrideDecodesNothingAndOptionalArraysStayParallel) {
  std::string dir = test::TempDir();
  WriteUvModel(dir);
  std::ofstream(dir + "/tri.obj") << "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nf 1 2 3\nf 2 4 3\n";
  // The scene's material reads no texture: nothing is decoded and no coordinates are kept.
  SceneDesc grey = LoadMeshes(dir, R"({"type": "mesh", "file": "m.gltf", "material": "grey"})");
  EXPECT_TRUE(grey.textures.empty());
  EXPECT_TRUE(grey.texels.empty());
  EXPECT_TRUE(grey.triangleUvs.empty());
  EXPECT_TRUE(grey.triangleColors.empty());
  // OBJ first (no coordinates), then the glTF with its own materials, then OBJ again.
  SceneDesc s = LoadMeshes(dir, R"({"type": "mesh", "file": "tri.obj"},
      {"type": "mesh", "file": "m.gltf"}, {"type": "mesh", "file": "tri.obj"})");
  ASSERT_EQ(s.triangles.size(), 2u + 6u + 2u);
  ASSERT_EQ(s.triangleUvs.size(), s.triangles.size());
  ASSERT_EQ(s.triangleUvs1.size(), s.triangles.size());
  for (size_t i : {0u, 1u, 8u, 9u}) ExpectUv(s.triangleUvs[i].uv1, vec2(0));
  ExpectUv(s.triangleUvs[3].uv1, vec2(1, 1));
  EXPECT_TRUE(s.triangleColors.empty());  // no COLOR_0 in the file
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
  EXPECT_EQ(m.type, MaterialType::kGltfPbr);
  EXPECT_FLOAT_EQ(m.metallic, 0.0f);
  EXPECT_FLOAT_EQ(m.roughness, 1.0f);
  ASSERT_EQ(m.baseColorTexture, 0);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].width, 512u);
  EXPECT_EQ(s.textures[0].height, 512u);
  EXPECT_EQ(s.textures[0].levels, 10u);  // 512 down to 1
  uint32_t levels = 0;
  EXPECT_EQ(s.texels.size(), PyramidTexelCount(512, 512, &levels));  // 4 bytes each, 4/3 x 512^2
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // A yellow duck: the texture's mean is yellow (red and green well above blue).
  glm::dvec3 mean(0.0);
  for (uint32_t i = 0; i < 512u * 512u; ++i) {
    for (int c = 0; c < 3; ++c) mean[c] += Srgb8ToLinear(uint8_t(s.texels[i] >> (8 * c)));
  }
  mean /= double(512 * 512);
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
