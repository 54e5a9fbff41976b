// A "material zoo": every material type, plain and textured, on tiles interleaved in screen
// space (neighbouring pixels hit different materials), lit by an emissive tile and a point
// light. Shared by the sort-mode tests (CPU bit-identity, GPU agreement).
#pragma once

#include <string>
#include <vector>

#include "src/io/scene_loader.h"
#include "src/scene/scene.h"
#include "tests/gltf_writer.h"

namespace pt::test {

// JSON materials; those named "*_t" get the glTF file's base colour texture after loading
// (JSON materials name no textures; the renderer applies one to any type).
inline const char* kZooJsonMaterials = R"({
  "diffuse": {"type": "diffuse", "albedo": [0.7, 0.6, 0.5]},
  "diffuse_t": {"type": "diffuse", "albedo": [0.9, 0.9, 0.9]},
  "conductor": {"type": "conductor", "albedo": [0.9, 0.7, 0.4], "roughness": 0.3},
  "mirror": {"type": "conductor", "albedo": [0.9, 0.9, 0.9]},
  "conductor_t": {"type": "conductor", "albedo": [0.9, 0.9, 0.9], "roughness": 0.2},
  "glass": {"type": "dielectric", "ior": 1.5},
  "rough_glass": {"type": "dielectric", "ior": 1.5, "roughness": 0.3},
  "glass_t": {"type": "dielectric", "ior": 1.33},
  "plastic": {"type": "plastic", "albedo": [0.2, 0.5, 0.8], "ior": 1.5, "roughness": 0.2},
  "plastic_t": {"type": "plastic", "albedo": [0.8, 0.8, 0.8], "ior": 1.5},
  "glow": {"type": "emissive", "radiance": [3, 3, 3]},
  "glow_t": {"type": "emissive", "radiance": [2, 2, 2]}
})";

// tiles x tiles squares of side 1 in the plane z = 0, tile i of material i mod the count (the
// glTF materials, plain and textured, among them), seen head-on by a camera at z = 4.
inline SceneDesc MaterialZooDesc(const std::string& dir, int tiles, int size, int spp,
                                 int maxDepth) {
  std::vector<std::string> json = {"diffuse", "diffuse_t", "conductor", "mirror",
                                   "conductor_t", "glass", "rough_glass", "glass_t",
                                   "plastic", "plastic_t", "glow", "glow_t"};
  const int kGltfKinds = 2;  // plain, textured
  int kinds = int(json.size()) + kGltfKinds;
  GltfWriter w("zoo");
  RgbaImage checker(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      uint8_t v = (x + y) % 2 ? 230 : 60;
      checker.Set(x, y, v, uint8_t(255 - v), 128, 255);
    }
  int tex = w.AddTexture(checker);
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.3, 1],
                    "metallicFactor": 0.2, "roughnessFactor": 0.4}})");
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorTexture": {"index": )" +
                std::to_string(tex) + R"(}, "metallicFactor": 0.7, "roughnessFactor": 0.3}})");
  std::string objects;
  float half = 0.5f * float(tiles);
  for (int i = 0; i < tiles * tiles; ++i) {
    int kind = i % kinds;
    float x = float(i % tiles) - half + 0.5f, y = float(i / tiles) - half + 0.5f;
    if (kind < int(json.size())) {
      if (!objects.empty()) objects += ", ";
      objects += R"({"type": "quad", "origin": [)" + std::to_string(x - 0.45f) + ", " +
                 std::to_string(y - 0.45f) + R"(, 0], "u": [0.9, 0, 0], "v": [0, 0.9, 0],
                 "material": ")" + json[kind] + "\"}";
    } else {
      GltfPrimitive sq = Square(0.45f, 0.0f, kind - int(json.size()));
      for (vec3& p : sq.positions) p += vec3(x, y, 0.0f);
      w.AddPrimitive(sq);
    }
  }
  objects += R"(, {"type": "mesh", "file": ")" + w.Write(dir) + "\"}";
  std::string text = R"({"render": {"width": )" + std::to_string(size) + R"(, "height": )" +
                     std::to_string(size) + R"(, "spp": )" + std::to_string(spp) +
                     R"(, "max_depth": )" + std::to_string(maxDepth) +
                     R"(, "seed": 7}, "camera": {"position": [0.3, 0.2, )" +
                     std::to_string(1.2f * float(tiles)) +
                     R"(], "look_at": [0, 0, 0], "fov_y": 50}, "materials": )" +
                     kZooJsonMaterials + R"(, "objects": [)" + objects +
                     R"(], "lights": [{"type": "point", "position": [1, 2, 3],
                     "intensity": [20, 20, 20]}]})";
  SceneDesc desc = LoadSceneFromString(text, "zoo.json", dir);
  int32_t texRef = -1;
  for (const Material& m : desc.materials)
    if (m.type == MaterialType::kGltfPbr && m.baseColorTexture >= 0) texRef = m.baseColorTexture;
  for (size_t m = 0; m < desc.materials.size(); ++m) {
    const std::string& name = desc.materialNames[m];
    if (name.size() > 2 && name.compare(name.size() - 2, 2, "_t") == 0)
      desc.materials[m].baseColorTexture = texRef;
  }
  return desc;
}

}  // namespace pt::test
