// Scenes whose shading normals disagree with their geometry, shared by the CPU tests
// (tests/shading_normals_test.cpp) and the GPU agreement test: icospheres with smooth or random
// vertex normals, a square whose normals tilt away from the viewer, and a square with a random
// normal texture in a white furnace.
#pragma once

#include <random>
#include <string>

#include "src/io/scene_loader.h"
#include "tests/gltf_material_scenes.h"
#include "tests/icosphere.h"

namespace pt::test {

// Icosphere of radius r with radial vertex normals (what a smooth-shaded export carries), or
// with random unit vertex normals (`wild`, seeded).
inline void AddNormalTestIcosphere(SceneDesc& d, vec3 centre, float r, int subdivisions, uint32_t material,
                  bool smooth, uint32_t wildSeed = 0) {
  UnitIcosphere m = MakeUnitIcosphere(subdivisions);
  std::mt19937 rng(wildSeed);
  std::normal_distribution<float> gauss;
  auto at = [&](uint32_t i) { return centre + r * vec3(m.vertices[i]); };
  auto normal = [&](uint32_t i) {
    if (wildSeed == 0) return vec3(m.vertices[i]);
    return glm::normalize(vec3(gauss(rng), gauss(rng), gauss(rng)));
  };
  for (glm::uvec3 f : m.faces) {
    d.triangles.push_back({at(f.x), at(f.y), at(f.z)});
    if (smooth) d.triangleNormals.push_back({normal(f.x), normal(f.y), normal(f.z)});
    else d.triangleNormals.push_back({vec3(0.0f), vec3(0.0f), vec3(0.0f)});  // none: flat
    d.triangleMaterials.push_back(material);
  }
}

inline const char* const kNormalTestMaterials = R"({
  "diffuse": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
  "mirror": {"type": "conductor", "albedo": [1, 1, 1], "roughness": 0},
  "rough": {"type": "conductor", "albedo": [1, 1, 1], "roughness": 0.4},
  "plastic": {"type": "plastic", "albedo": [0.8, 0.8, 0.8], "ior": 1.5, "roughness": 0.2}})";
enum NormalTestMaterial : uint32_t { kNtDiffuse = 0, kNtMirror, kNtRough, kNtPlastic };

inline SceneDesc NormalTestScene(const char* extra, const char* camera = R"({"position": [0, 0, 4],
    "look_at": [0, 0, 0], "fov_y": 35})") {
  std::string json = std::string(R"({
    "render": {"width": 32, "height": 32, "spp": 64, "max_depth": 4, "seed": 3},
    "camera": )") + camera + R"(, "materials": )" + kNormalTestMaterials + R"(, "objects": [])" + extra +
                     "}";
  return LoadSceneFromString(json, "shading-normals.json", ".");
}

// The square [-1, 1]^2 (z = 0, facing +z) whose vertex normals all tilt `degrees` towards +x,
// seen from (-2.6, 0, 1.5) (60 degrees off its normal, on the -x side): every shading normal
// faces away from the viewer, which the triangles face.
inline SceneDesc TiltedNormalSquare(uint32_t material, float degrees) {
  SceneDesc d = NormalTestScene(R"(, "background": [1, 1, 1])", R"({"position": [-2.598, 0, 1.5],
      "look_at": [0, 0, 0], "fov_y": 12})");
  vec3 p[4] = {vec3(-1, -1, 0), vec3(1, -1, 0), vec3(1, 1, 0), vec3(-1, 1, 0)};
  float a = glm::radians(degrees);
  vec3 n(std::sin(a), 0.0f, std::cos(a));
  for (auto [i, j, k] : {std::array{0, 1, 2}, std::array{0, 2, 3}}) {
    d.triangles.push_back({p[i], p[j], p[k]});
    d.triangleNormals.push_back({n, n, n});
    d.triangleMaterials.push_back(material);
  }
  return d;
}

// The square filling a far camera's view, glTF material `index` of kFurnaceMaterials (white
// base colour) with a 16 x 16 normal texture of random texels, under a uniform environment of
// radiance 1.
inline const char* const kFurnaceMaterials[] = {
    R"("metallicFactor": 0, "roughnessFactor": 1)",
    R"("metallicFactor": 0, "roughnessFactor": 0.3)",
    R"("metallicFactor": 1, "roughnessFactor": 0.5)",
    R"("metallicFactor": 1, "roughnessFactor": 0)",
};

inline Scene WildNormalFurnace(const std::string& dir, int index, const SceneSpec& spec) {
  RgbaImage wild(16, 16);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> code(0, 255);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      wild.Set(x, y, uint8_t(code(rng)), uint8_t(code(rng)), uint8_t(128 + code(rng) / 2), 255);
  GltfWriter w("furnace" + std::to_string(index));
  int tex = w.AddTexture(wild);
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], )" +
                std::string(kFurnaceMaterials[index]) + R"(}, "normalTexture": {"index": )" +
                std::to_string(tex) + "}}");
  w.AddPrimitive(Square());
  return LoadGenerated(dir, spec, FarCamera(0.9),
                       R"({"type": "mesh", "file": ")" + w.Write(dir) + "\"}",
                       R"(, "background": [1, 1, 1])");
}

}  // namespace pt::test
