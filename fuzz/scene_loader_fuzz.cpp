// libFuzzer target for the scene loader: arbitrary bytes as a scene file. LoadSceneFromString
// may refuse them only with a SceneError; any other exception (it escapes and aborts), a crash,
// a sanitizer report, a leak or a hang is a finding. A scene the loader accepts must also
// build (BVH and light table), which may refuse only with std::runtime_error, as documented
// for BuildScene.
//
// Inputs that start with the GLB magic "glTF" are fuzzed as a binary glTF mesh instead: they
// are written to a scratch file and loaded through a fixed scene that refers to it, so the
// glTF path (tinygltf's container and JSON parsing, our accessor and node walking) is reached
// from the GLB seeds too; the same file is then loaded as the whole scene (its cameras,
// KHR_lights_punctual lights, the automatic camera and the default environment).
//
// Environment: PT_FUZZ_BASE_DIR is the folder relative mesh paths resolve against (default
// "."); tools/run_fuzz.sh points it at a folder whose meshes/ holds the seeds' meshes.
// Build and run with tools/run_fuzz.sh.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "src/io/scene_loader.h"
#include "src/scene/scene.h"

namespace {

std::string Env(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

const std::string& BaseDir() {
  static const std::string dir = Env("PT_FUZZ_BASE_DIR", ".");
  return dir;
}

// One scratch file per process (libFuzzer's -jobs/-fork workers are separate processes).
const std::string& ScratchGlb() {
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("pt_fuzz_" + std::to_string(getpid()) + ".glb")).string();
  return path;
}

// A scene text, or (text empty) the model file `name` as the whole scene.
void LoadAndBuild(const std::string& text, const std::string& name) {
  pt::SceneDesc desc;
  try {
    desc = text.empty() ? pt::LoadScene(name) : pt::LoadSceneFromString(text, name, BaseDir());
  } catch (const pt::SceneError&) {
    return;  // the one allowed refusal
  }
  try {
    pt::Scene scene = pt::BuildScene(std::move(desc));
    (void)scene;
  } catch (const std::runtime_error&) {
    // BuildScene's documented refusal of a scene it cannot render.
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0) {
    {
      std::ofstream out(ScratchGlb(), std::ios::binary | std::ios::trunc);
      out.write(bytes.data(), std::streamsize(bytes.size()));
    }
    std::string scene = R"({
      "render": {"width": 4, "height": 4, "spp": 1, "max_depth": 1},
      "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_y": 40},
      "materials": {}, "objects": [{"type": "mesh", "file": ")" + ScratchGlb() + R"("}]})";
    LoadAndBuild(scene, "fuzz-glb-scene.json");
    LoadAndBuild("", ScratchGlb());
    return 0;
  }
  LoadAndBuild(bytes, "fuzz-input.json");
  return 0;
}
