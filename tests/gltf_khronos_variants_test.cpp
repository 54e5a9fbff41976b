// The Khronos sample models' compressed variants against their plain files, when the samples
// are fetched (they are third-party files kept out of the repository): the folder
// PT_GLTF_SAMPLES names, by default ../assets_extra beside the repository, holding
// <Model>/glTF/<Model>.gltf and <Model>/glTF-Draco/<Model>.gltf as in KhronosGroup's
// glTF-Sample-Assets. Both are posed at 0.7 s of their animation (the skinned ones bend by
// their decoded joints and weights). Their Draco files are quantised (positions to 11-14 bits, normals and
// UVs to 8-10): every decoded vertex must lie within 2^-10 of the model's size of a plain one,
// and 99% of the triangles must match one of the plain file's with normals and UVs close. The
// repository of samples has no meshopt or WebP variants of these models, so the plain files are
// re-encoded here (lossless) and must load to the same triangles and texels bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "src/io/scene_loader.h"
#include "tests/gltf_transcode.h"
#include "tests/mesh_compare.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string SamplesDir() {
  const char* env = std::getenv("PT_GLTF_SAMPLES");
  return env ? env : test::SourcePath("../assets_extra");
}

// The model's file in that variant folder, or "" when it is not fetched (or a placeholder of a
// file too large for the snapshot: empty).
std::string SampleFile(const std::string& model, const std::string& variant) {
  fs::path path = fs::path(SamplesDir()) / model / variant / (model + ".gltf");
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) > 0 ? path.string() : "";
}

float Diagonal(const SceneDesc& s) {
  vec3 lo(INFINITY), hi(-INFINITY);
  for (const Triangle& t : s.triangles)
    for (vec3 p : {t.p0, t.p1, t.p2}) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

TEST(GltfKhronosVariants, DracoFilesMatchThePlainOnes) {
  int compared = 0;
  for (const char* model : {"Box", "Duck", "CesiumMan", "RiggedSimple", "CesiumMilkTruck", "BrainStem"}) {
    std::string plainPath = SampleFile(model, "glTF"), dracoPath = SampleFile(model, "glTF-Draco");
    if (plainPath.empty() || dracoPath.empty()) continue;
    ++compared;
    LoadOptions posed;  // skinned models (decoded JOINTS_0 and WEIGHTS_0) at a mid-walk pose
    posed.time = 0.7;
    SceneDesc plain = LoadScene(plainPath, posed), draco = LoadScene(dracoPath, posed);
    // Draco drops faces that quantisation collapses (BrainStem: 24 of 61,666).
    size_t fewer = plain.triangles.size() - std::min(plain.triangles.size(), draco.triangles.size());
    EXPECT_LE(draco.triangles.size(), plain.triangles.size()) << model;
    EXPECT_LE(fewer, plain.triangles.size() / 1000) << model;
    float step = Diagonal(plain) * std::ldexp(1.0f, -10);
    test::MeshComparer comparer(plain, step * 2.0f);
    test::MeshCompareResult r = comparer.Compare(plain, draco, {step, 0.06f, 2e-3f});
    EXPECT_EQ(r.farCorners, 0u) << model;
    EXPECT_LE(r.unmatched + r.attributeMisses, fewer + r.triangles / 100) << model << ": " << r.unmatched
                                                                  << " unmatched, " << r.attributeMisses
                                                                  << " with other normals or UVs";
  }
  if (compared == 0) GTEST_SKIP() << "no Khronos Draco samples under " << SamplesDir();
}

TEST(GltfKhronosVariants, MeshoptAndWebpReencodingsEqualThePlainFiles) {
  int compared = 0;
  for (const char* model : {"Duck", "CesiumMan", "CesiumMilkTruck"}) {
    std::string plainPath = SampleFile(model, "glTF");
    if (plainPath.empty()) continue;
    ++compared;
    SceneDesc plain = LoadScene(plainPath);
    std::string dir = test::TempDir();
    test::GltfFiles meshopt = test::MeshoptCompressed(test::ReadGltfFiles(plainPath));
    SceneDesc decoded = LoadScene(test::WriteGltfFiles(meshopt, dir, "meshopt"));
    EXPECT_TRUE(test::BitIdentical(plain.triangles, decoded.triangles)) << model;
    EXPECT_TRUE(test::BitIdentical(plain.triangleNormals, decoded.triangleNormals)) << model;
    EXPECT_TRUE(test::BitIdentical(plain.triangleUvs, decoded.triangleUvs)) << model;
    test::GltfFiles webp = test::ReadGltfFiles(plainPath);
    if (!webp.doc.contains("images")) continue;
    test::WebpTextures(webp, dir, false);
    SceneDesc fromWebp = LoadScene(test::WriteGltfFiles(webp, dir, "webp"));
    EXPECT_FALSE(plain.texels.empty()) << model;
    EXPECT_EQ(plain.texels, fromWebp.texels) << model;
  }
  if (compared == 0) GTEST_SKIP() << "no Khronos samples under " << SamplesDir();
}

}  // namespace
}  // namespace pt
