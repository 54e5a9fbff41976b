// Compressed and modern glTF (src/io/gltf_document.h): files encoded here with Debian's
// libdraco, libmeshoptimizer and libwebp decode to the plain file's triangles and texels
// (Draco lossless and meshopt exactly, quantised Draco within its step, lossless WebP texel
// for texel); KHR_texture_basisu uses its fallback image and is refused naming KTX2 without
// one; truncated or corrupt compressed data is a clear error (exit 2, nothing written). When
// the Khronos sample models are fetched (PT_GLTF_SAMPLES, default ../assets_extra beside the
// repository: <Model>/glTF/ and <Model>/glTF-Draco/), their Draco variants must match the
// plain files and meshopt/WebP re-encodings of the plain files must equal them exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "src/io/scene_loader.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"
#include "tests/gltf_grid_files.h"
#include "tests/gltf_transcode.h"
#include "tests/mesh_compare.h"
#include "tests/texture_test_util.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

test::MeshCompareResult CompareMeshes(const SceneDesc& plain, const SceneDesc& decoded,
                                      test::MeshCompareTolerance tol) {
  test::MeshComparer comparer(plain, std::max(tol.position, 1e-4f) * 2.0f);
  return comparer.Compare(plain, decoded, tol);
}

std::string LoadError(const std::string& path) {
  try {
    LoadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(GltfCompressed, LosslessDracoDecodesToThePlainMesh) {
  std::string dir = test::TempDir();
  test::GridMesh m = test::WavyGrid(7);
  SceneDesc plain = LoadScene(test::WritePlainGrid(dir, m));
  SceneDesc draco = LoadScene(test::WriteDracoGrid(dir, "draco", m, 0, 0, 0));
  ASSERT_EQ(draco.triangles.size(), m.idx.size() / 3);
  ASSERT_EQ(draco.triangleUvs.size(), draco.triangles.size());
  test::MeshCompareResult r = CompareMeshes(plain, draco, {});
  EXPECT_EQ(r.farCorners, 0u);
  EXPECT_EQ(r.unmatched, 0u);
  EXPECT_EQ(r.attributeMisses, 0u);
  EXPECT_EQ(plain.texels, draco.texels);
}

TEST(GltfCompressed, QuantisedDracoIsWithinItsQuantisationStep) {
  std::string dir = test::TempDir();
  test::GridMesh m = test::WavyGrid(9);
  SceneDesc plain = LoadScene(test::WritePlainGrid(dir, m));
  SceneDesc draco = LoadScene(test::WriteDracoGrid(dir, "draco", m, 11, 10, 10));
  // Draco quantises each attribute over its bounding box's largest side: step = side / (2^bits - 1).
  float side = 2.0f * 1.37f, step = side / 2047.0f;
  test::MeshCompareResult exact = CompareMeshes(plain, draco, {});
  EXPECT_GT(exact.farCorners, 0u) << "quantisation moved no vertex: the test cannot tell";
  test::MeshCompareResult r = CompareMeshes(plain, draco, {step, 4.0f / 1023.0f, 1.0f / 1023.0f});
  EXPECT_EQ(r.farCorners, 0u);
  EXPECT_EQ(r.unmatched, 0u);
  EXPECT_EQ(r.attributeMisses, 0u);
}

TEST(GltfCompressed, MeshoptViewsDecodeExactlyUnderBothExtensionNames) {
  std::string dir = test::TempDir();
  SceneDesc plain = LoadScene(test::WritePlainGrid(dir, test::WavyGrid(6)));
  for (bool khr : {false, true}) {
    std::string out = dir + (khr ? "/khr" : "/ext");
    fs::create_directories(out);
    test::GltfFiles files = test::MeshoptCompressed(test::ReadGltfFiles(dir + "/plain.gltf"), khr);
    SceneDesc decoded = LoadScene(test::WriteGltfFiles(files, out, "meshopt"));
    EXPECT_TRUE(test::BitIdentical(plain.triangles, decoded.triangles)) << khr;
    EXPECT_TRUE(test::BitIdentical(plain.triangleNormals, decoded.triangleNormals)) << khr;
    EXPECT_TRUE(test::BitIdentical(plain.triangleUvs, decoded.triangleUvs)) << khr;
    EXPECT_EQ(plain.texels, decoded.texels);
  }
}

// meshopt's filters: octahedral int8 normals and exponential float positions.
TEST(GltfCompressed, MeshoptFiltersAreUndone) {
  test::GridMesh m = test::WavyGrid(5);
  size_t count = m.p.size();
  std::vector<float> normals4, positions;
  for (size_t i = 0; i < count; ++i) {
    normals4.insert(normals4.end(), {m.n[i].x, m.n[i].y, m.n[i].z, 0.0f});
    positions.insert(positions.end(), {m.p[i].x, m.p[i].y, m.p[i].z});
  }
  std::vector<int8_t> octahedral(count * 4);
  meshopt_encodeFilterOct(octahedral.data(), count, 4, 8, normals4.data());
  std::vector<uint32_t> exponential(count * 3);
  meshopt_encodeFilterExp(exponential.data(), count, 12, 18, positions.data());
  auto encode = [](const void* data, size_t n, size_t stride) {
    std::vector<unsigned char> out(meshopt_encodeVertexBufferBound(n, stride));
    out.resize(meshopt_encodeVertexBuffer(out.data(), out.size(), data, n, stride));
    return std::string(out.begin(), out.end());
  };
  test::GltfSceneWriter w;
  int posView = w.AddView(encode(exponential.data(), count, 12));
  int norView = w.AddView(encode(octahedral.data(), count, 4));
  int idx = w.AddAccessor(m.idx.data(), m.idx.size(), 4, 5125, "SCALAR");
  json& views = w.doc["bufferViews"];
  auto compressed = [&](int v, size_t stride, const char* filter) {
    json ext = {{"buffer", 0}, {"byteOffset", views[v]["byteOffset"]}, {"byteLength", views[v]["byteLength"]},
                {"byteStride", stride}, {"mode", "ATTRIBUTES"}, {"count", count}, {"filter", filter}};
    views[v] = {{"buffer", 1}, {"byteOffset", 0}, {"byteLength", count * stride}, {"byteStride", stride},
                {"extensions", {{"EXT_meshopt_compression", ext}}}};
  };
  compressed(posView, 12, "EXPONENTIAL");
  compressed(norView, 4, "OCTAHEDRAL");
  w.doc["accessors"].push_back({{"bufferView", posView}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}});
  w.doc["accessors"].push_back({{"bufferView", norView}, {"componentType", 5120}, {"normalized", true},
                                {"count", count}, {"type", "VEC3"}});
  w.doc["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", 1}, {"NORMAL", 2}}}, {"indices", idx}}}}});
  w.AddNode({{"mesh", 0}});
  w.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
  std::string path = w.Write(test::TempDir(), "filters");
  json doc = json::parse(test::ReadText(path));  // the fallback buffer: no data
  doc["buffers"].push_back({{"byteLength", count * 12}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
  std::ofstream(path) << doc.dump();
  SceneDesc s = LoadScene(path);
  ASSERT_EQ(s.triangles.size(), m.idx.size() / 3);
  float worst = 0.0f, worstNormal = 0.0f;
  for (size_t t = 0; t < s.triangles.size(); ++t) {
    const vec3* p = &s.triangles[t].p0;
    const vec3* n = &s.triangleNormals[t].n0;
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, glm::length(p[k] - m.p[m.idx[3 * t + size_t(k)]]));
      worstNormal = std::max(worstNormal, glm::length(glm::normalize(n[k]) - m.n[m.idx[3 * t + size_t(k)]]));
    }
  }
  EXPECT_LT(worst, 2.0f * std::ldexp(1.0f, -17));  // 18-bit mantissas of values below 2
  EXPECT_GT(worst, 0.0f) << "the filter changed nothing: the test cannot tell";
  EXPECT_LT(worstNormal, 0.02f);                   // 8-bit octahedral
}

// Truncated Draco data: a .bin cut short, then a Draco view cut short. Both are bad input
// naming the file and the part, and the command line writes nothing.
TEST(GltfCompressed, TruncatedDracoDataIsRefusedNamingFileAndPart) {
  std::string dir = test::TempDir();
  std::string path = test::WriteDracoGrid(dir, "draco", test::WavyGrid(6), 0, 0, 0);
  std::string bin = test::ReadBinaryFile(dir + "/draco.bin");
  test::WriteFile(dir + "/draco.bin", bin.substr(0, bin.size() / 2));
  EXPECT_EQ(LoadError(path), path + ": buffers[0]: holds " + std::to_string(bin.size() / 2) +
                                 " bytes, fewer than its byteLength " + std::to_string(bin.size()) +
                                 " (truncated)");
  test::ExpectRefusedWritingNothing(path, "", dir);
  test::WriteFile(dir + "/draco.bin", bin);
  json doc = json::parse(test::ReadText(path));
  doc["bufferViews"][0]["byteLength"] = doc["bufferViews"][0]["byteLength"].get<int>() / 2;
  std::ofstream(path) << doc.dump();
  std::string message = LoadError(path);
  EXPECT_EQ(message.rfind(path + ": meshes[0].primitives[0].extensions.KHR_draco_mesh_compression: "
                                 "Draco cannot decode its ", 0), 0u) << message;
  test::ExpectRefusedWritingNothing(path, "", dir);
}

TEST(GltfCompressed, CorruptMeshoptDataIsRefusedNamingThePart) {
  std::string dir = test::TempDir();
  test::WritePlainGrid(dir, test::WavyGrid(3));
  test::GltfFiles files = test::MeshoptCompressed(test::ReadGltfFiles(dir + "/plain.gltf"));
  json good = files.doc;
  files.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 5;
  std::string path = test::WriteGltfFiles(files, dir, "meshopt");
  std::string message = LoadError(path);
  EXPECT_EQ(message.rfind(path + ": bufferViews[0].extensions.EXT_meshopt_compression: meshopt "
                                 "cannot decode its 5 bytes (ATTRIBUTES, count ", 0), 0u) << message;
  // A plain view that reads the fallback buffer, which holds no data.
  files.doc = good;
  files.doc["bufferViews"][1].erase("extensions");
  path = test::WriteGltfFiles(files, dir, "meshopt");
  message = LoadError(path);
  EXPECT_NE(message.find(": bufferViews[1]: bytes "), std::string::npos) << message;
  EXPECT_NE(message.find("lie outside buffer 1 (0 bytes, a meshopt fallback without data)"),
            std::string::npos) << message;
  // An unknown filter.
  files.doc = good;
  files.doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["filter"] = "SPIRAL";
  path = test::WriteGltfFiles(files, dir, "meshopt");
  EXPECT_NE(LoadError(path).find("bufferViews[0].extensions.EXT_meshopt_compression.filter: "
                                 "unknown filter \"SPIRAL\""), std::string::npos);
  test::ExpectRefusedWritingNothing(path, "", dir);
}

}  // namespace
}  // namespace pt
