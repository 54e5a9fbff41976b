// Helpers for environment-map tests: a temporary folder removed at the end of the test, maps
// written as PFM files, and scenes loaded from JSON text whose map paths resolve there.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "src/io/image_io.h"
#include "src/io/scene_loader.h"
#include "tests/test_util.h"

namespace pt::test {

// A fresh folder, removed with everything in it when the test ends.
struct ScopedDir {
  std::string path = TempDir();
  ~ScopedDir() { std::filesystem::remove_all(path); }
  std::string operator/(const std::string& name) const { return path + "/" + name; }
};

// Writes a width x width/2 map whose texel (i, j) (row 0 at the top) is texel(i, j).
inline void WriteMap(const std::string& path, int width,
                     const std::function<vec3(int i, int j)>& texel) {
  FilmImage image;
  image.width = width;
  image.height = width / 2;
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < width; ++i) {
      vec3 t = texel(i, j);
      image.rgb.insert(image.rgb.end(), {t.x, t.y, t.z});
    }
  WriteImage(path, image);
}

inline Scene SceneIn(const ScopedDir& dir, const std::string& json) {
  return BuildScene(LoadSceneFromString(json, "env-test-scene.json", dir.path));
}

}  // namespace pt::test
