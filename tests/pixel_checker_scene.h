// A square filling the image with an emissive checker whose checks are exactly one pixel
// (4 x 4 texels each: the texture has 4 texels per pixel), for the texture footprint's rule
// (src/materials/surface_attributes.h: 1 / sqrt(spp) of a pixel, at least 1/8). Shared by the
// CPU test (analytic contrasts) and the GPU agreement test.
#pragma once

#include <string>

#include "tests/gltf_material_scenes.h"

namespace pt::test {

// Whether pixel (x, y) lies on a white check.
inline bool PixelCheckIsWhite(int x, int y) { return (x + y) % 2 == 1; }

// Writes the model for an image of size x size pixels into dir; returns its file name.
inline std::string WritePixelCheckerModel(const std::string& dir, int size) {
  const int texels = 4 * size;
  RgbaImage img(texels, texels);
  for (int y = 0; y < texels; ++y)
    for (int x = 0; x < texels; ++x) {
      uint8_t c = PixelCheckIsWhite(x / 4, y / 4) ? 255 : 0;
      img.Set(x, y, c, c, c, 255);
    }
  GltfWriter w("pixel_checker" + std::to_string(size));
  int tex = w.AddTexture(img);
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                    "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": )" +
                std::to_string(tex) + "}}");
  w.AddPrimitive(Square());
  return w.Write(dir);
}

inline Scene PixelCheckerScene(const std::string& dir, const SceneSpec& spec) {
  return LoadGenerated(dir, spec, FarCamera(1.0),
                       R"({"type": "mesh", "file": ")" + WritePixelCheckerModel(dir, spec.size) +
                           "\"}");
}

}  // namespace pt::test
