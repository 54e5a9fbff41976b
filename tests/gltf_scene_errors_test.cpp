// Bad input given as the whole scene (`pathtracer FILE.gltf`): the corpus of broken glTF files
// in tests/malformed/gltf/ (accessors, nodes and meshes that do not exist, index types and
// values out of range, truncated JSON, a missing .bin, a missing or undecodable texture), every
// broken mesh file of tests/malformed/meshes/, and an unknown --camera. Each is a SceneError
// naming the file and the part; the CLI exits 2, naming the file, and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "src/io/scene_loader.h"
#include "src/scene/scene.h"
#include "tests/cli_test_util.h"
#include "tests/gltf_scene_writer.h"
#include "tests/test_util.h"

namespace pt {
namespace {

namespace fs = std::filesystem;

// Each glTF of the corpus and a phrase naming the broken part that its message must contain.
const std::map<std::string, std::string>& GltfCorpus() {
  static const std::map<std::string, std::string> corpus = {
      {"accessor_index_out_of_range.gltf", "meshes[0].primitives[0]: accessor 7 does not exist"},
      {"indices_accessor_out_of_range.gltf", "indices accessor out of bounds"},
      {"indices_float_component_type.gltf",
       "meshes[0].primitives[0]: index accessor 1 is not of an unsigned integer type"},
      {"position_unknown_component_type.gltf", "Invalid `componentType` in accessor"},
      {"index_out_of_range.gltf", "meshes[0].primitives[0]: index 1065353216 out of range"},
      {"node_mesh_out_of_range.gltf", "nodes[0].mesh: mesh 3 does not exist"},
      {"scene_node_out_of_range.gltf", "node 5 does not exist"},
      {"truncated_json.gltf", "cannot load glTF: [json.exception.parse_error"},
      {"missing_bin.gltf", "File not found : missing.bin"},
      {"missing_texture.gltf", "material \"painted\" (#0): image #0 (\"missing.png\") cannot be read"},
      {"unreadable_texture.gltf", "material \"painted\" (#0): image #0 cannot be decoded"},
  };
  return corpus;
}

std::string MalformedDir(const std::string& sub) {
  return test::SourcePath("tests/malformed/" + sub);
}

std::vector<std::string> FilesIn(const std::string& dir, bool gltfOnly) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::string name = entry.path().filename().string();
    if (!gltfOnly || entry.path().extension() == ".gltf") names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// LoadScene's refusal of `path` (with `options`), or "" with a failure when it is accepted.
std::string Refusal(const std::string& path, const LoadOptions& options = {}) {
  try {
    BuildScene(LoadScene(path, options));
    ADD_FAILURE() << path << " was accepted";
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(GltfSceneErrors, CorpusMatchesItsList) {
  std::vector<std::string> files = FilesIn(MalformedDir("gltf"), true);
  for (const std::string& f : files) EXPECT_TRUE(GltfCorpus().count(f)) << f << " is not listed";
  EXPECT_EQ(files.size(), GltfCorpus().size());
}

TEST(GltfSceneErrors, EveryBrokenFileIsASceneErrorNamingFileAndPart) {
  for (const auto& [name, phrase] : GltfCorpus()) {
    std::string path = MalformedDir("gltf") + "/" + name;
    std::string m = Refusal(path);
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << name << ": the message does not start with the file: " << m;
    EXPECT_NE(m.find(phrase), std::string::npos) << name << ": '" << phrase << "' in: " << m;
  }
  // The broken mesh files the JSON corpus includes, now as the whole scene.
  for (const std::string& name : FilesIn(MalformedDir("meshes"), false)) {
    std::string path = MalformedDir("meshes") + "/" + name;
    std::string m = Refusal(path);
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << name << ": the message does not start with the file: " << m;
  }
}

// A valid file: the floor and the camera "Main".
std::string WriteGoodScene(const std::string& dir) {
  test::GltfSceneWriter w;
  w.AddCamera(test::GltfSceneWriter::Perspective(0.7, 1.0, "Main"));
  w.AddNode({{"mesh", w.AddFloor(1.0f)}});
  w.AddNode({{"camera", 0}, {"translation", {0, 1, 3}}});
  return w.Write(dir, "good", /*glb=*/true);
}

TEST(GltfSceneErrors, UnknownCameraNamesTheOptionAndListsTheCameras) {
  std::string path = WriteGoodScene(test::TempDir());
  LoadOptions options;
  options.camera = "Back";
  std::string m = Refusal(path, options);
  EXPECT_EQ(m.rfind(path + ": --camera: ", 0), 0u) << m;
  EXPECT_NE(m.find("\"Back\""), std::string::npos) << m;
  EXPECT_NE(m.find("0 \"Main\""), std::string::npos) << m;
}

// The CLI: exit 2 with a message naming the file, the existing image untouched, nothing else
// written, for every broken file, an unknown camera and a missing model file.
TEST(GltfSceneErrors, CliExitsTwoNamingTheFileAndWritesNothing) {
  std::string dir = test::TempDir();
  std::string good = WriteGoodScene(dir);
  for (const auto& entry : GltfCorpus()) {
    test::ExpectRefusedWritingNothing(MalformedDir("gltf") + "/" + entry.first, "", dir);
  }
  for (const std::string& name : FilesIn(MalformedDir("meshes"), false)) {
    test::ExpectRefusedWritingNothing(MalformedDir("meshes") + "/" + name, "", dir);
  }
  test::ExpectRefusedWritingNothing(good, "--camera Back", dir);
  test::ExpectRefusedWritingNothing(dir + "/absent.glb", "", dir);
  // The same file renders: the refusal above is the camera's.
  EXPECT_EQ(test::RunPathtracer("'" + good + "' -o " + dir + "/good.png --width 8 --height 8 "
                                "--spp 1 --quiet"),
            0);
}

}  // namespace
}  // namespace pt
