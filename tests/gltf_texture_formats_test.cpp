// glTF textures beyond PNG and JPEG (src/io/gltf_image_formats.h): EXT_texture_webp images
// decoded by libwebp to the same texels as the PNG, preferred over a fallback source; a
// KHR_texture_basisu texture reads its fallback PNG, and without one the file is refused
// naming KTX2 before anything is parsed (exit 2, nothing written).
#include <gtest/gtest.h>

#include <filesystem>

#include "src/io/scene_loader.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_grid_files.h"
#include "tests/gltf_transcode.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

std::string TextureFormatError(const std::string& path) {
  try {
    LoadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

// The 12-byte KTX2 identifier and nothing a decoder could use.
std::string FakeKtx2() { return std::string("\xABKTX 20\xBB\r\n\x1A\n", 12) + std::string(64, '\0'); }

TEST(GltfTextureFormats, WebpTexturesDecodeToThePngTexelsAndWinOverTheFallback) {
  std::string dir = test::TempDir();
  std::string plainPath = test::WritePlainGrid(dir, test::WavyGrid(2));
  SceneDesc plain = LoadScene(plainPath);
  ASSERT_FALSE(plain.texels.empty());
  for (bool keepFallback : {true, false}) {
    std::string out = dir + (keepFallback ? "/with_fallback" : "/webp_only");
    fs::create_directories(out);
    test::GltfFiles files = test::ReadGltfFiles(plainPath);
    test::WebpTextures(files, out, keepFallback);
    std::string path = test::WriteGltfFiles(files, out, "webp");
    // The fallback PNG shows another picture: only the WebP gives the plain file's texels.
    if (keepFallback) test::WriteFile(out + "/grid.png", test::EncodePng(test::GridTexture(99)));
    SceneDesc s = LoadScene(path);
    EXPECT_EQ(plain.texels, s.texels) << (keepFallback ? "with" : "without") << " fallback";
  }
}

TEST(GltfTextureFormats, BrokenWebpIsAnErrorNamingTheImage) {
  std::string dir = test::TempDir();
  test::GltfFiles files = test::ReadGltfFiles(test::WritePlainGrid(dir, test::WavyGrid(1)));
  test::WebpTextures(files, dir, false);
  std::string path = test::WriteGltfFiles(files, dir, "webp");
  std::string webp = test::ReadBinaryFile(dir + "/image0.webp");
  test::WriteFile(dir + "/image0.webp", webp.substr(0, webp.size() / 2));
  std::string message = TextureFormatError(path);
  EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("image #1 (WebP) cannot be decoded"), std::string::npos) << message;
}

// A texture whose KHR_texture_basisu image is KTX2; `fallback`: it keeps its PNG source.
std::string WriteKtx2Grid(const std::string& dir, bool fallback, bool asSource = false) {
  test::GltfFiles files = test::ReadGltfFiles(test::WritePlainGrid(dir, test::WavyGrid(2)));
  test::WriteFile(dir + "/grid.ktx2", FakeKtx2());
  files.doc["images"].push_back({{"uri", "grid.ktx2"}, {"mimeType", "image/ktx2"}});
  nlohmann::json& texture = files.doc["textures"][0];
  if (asSource) {
    texture["source"] = 1;
  } else {
    texture["extensions"]["KHR_texture_basisu"]["source"] = 1;
    if (!fallback) texture.erase("source");
    files.doc["extensionsUsed"] = {"KHR_texture_basisu"};
    files.doc["extensionsRequired"] = {"KHR_texture_basisu"};
  }
  return test::WriteGltfFiles(files, dir, "ktx2");
}

TEST(GltfTextureFormats, BasisuTexturesReadTheirFallback) {
  std::string dir = test::TempDir();
  SceneDesc plain = LoadScene(test::WritePlainGrid(dir, test::WavyGrid(2)));
  SceneDesc s = LoadScene(WriteKtx2Grid(dir, true));
  EXPECT_EQ(plain.texels, s.texels);
}

TEST(GltfTextureFormats, Ktx2WithoutFallbackIsRefusedNamingKtx2) {
  std::string dir = test::TempDir();
  std::string path = WriteKtx2Grid(dir, false);
  EXPECT_EQ(TextureFormatError(path),
            path + ": textures[0]: its only image is KTX2 (KHR_texture_basisu) and it has no "
                   "fallback \"source\" (PNG or JPEG); this renderer cannot decode KTX2 / Basis "
                   "Universal");
  test::ExpectRefusedWritingNothing(path, "", dir);
  // A KTX2 image named as a plain source: refused when decoded, naming KTX2 too.
  path = WriteKtx2Grid(dir, true, true);
  std::string message = TextureFormatError(path);
  EXPECT_NE(message.find("image #1 is a KTX2 image (KHR_texture_basisu)"), std::string::npos)
      << message;
}

}  // namespace
}  // namespace pt
