// Small generated glTF scenes, one per material feature, shared by the CPU tests (analytic
// expectations, tests/gltf_material_render_test.cpp) and the GPU agreement tests. Each writes its
// files into dir and returns the scene, rendered at `size` x `size` with `spp` samples.
#pragma once

#include <cmath>
#include <string>

#include "src/io/scene_loader.h"
#include "tests/gltf_writer.h"

namespace pt::test {

struct SceneSpec {
  int size = 32, spp = 4, maxDepth = 1;
  uint32_t seed = 1;
};

// A camera at distance 60 on +z looking at the origin whose view just spans [-half, half]^2.
inline std::string FarCamera(double half) {
  double fov = 2.0 * std::atan(half / 60.0) * 180.0 / M_PI;
  return R"({"position": [0, 0, 60], "look_at": [0, 0, 0], "fov_y": )" + std::to_string(fov) + "}";
}

inline Scene LoadGenerated(const std::string& dir, const SceneSpec& spec, const std::string& camera,
                           const std::string& objects, const std::string& extra = "") {
  std::string json = R"({"render": {"width": )" + std::to_string(spec.size) +
                     R"(, "height": )" + std::to_string(spec.size) + R"(, "spp": )" +
                     std::to_string(spec.spp) + R"(, "max_depth": )" +
                     std::to_string(spec.maxDepth) + R"(, "russian_roulette_depth": 100, "seed": )" +
                     std::to_string(spec.seed) + R"(}, "camera": )" + camera +
                     R"(, "materials": {"floor": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
      "objects": [)" + objects + "]" + extra + "}";
  return BuildScene(LoadSceneFromString(json, "generated.json", dir));
}

// An 8 x 1 image: the left four texels `left`, the right four `right` (RGBA codes).
inline RgbaImage HalfAndHalf(const uint8_t left[4], const uint8_t right[4]) {
  RgbaImage img(8, 1);
  for (int x = 0; x < 8; ++x) {
    const uint8_t* c = x < 4 ? left : right;
    img.Set(x, 0, c[0], c[1], c[2], c[3]);
  }
  return img;
}

constexpr int kClamp = 33071;

// A square normal-mapped on its left half (the tangent-space normal of codes `tilted`), flat
// on its right, lit by a distant point light 45 degrees off the normal towards +x (irradiance
// 1 at normal incidence). Variants: 0 tangents from UVs, 1 TANGENT attribute, 2 scale 0.5.
inline const uint8_t kTiltedNormal[4] = {191, 128, 221, 255};  // ~34 degrees towards +x
inline const uint8_t kFlatNormal[4] = {128, 128, 255, 255};    // 8-bit: 0.2 degrees off
inline Scene NormalMapScene(const std::string& dir, int variant, const SceneSpec& spec) {
  const uint8_t* flat = kFlatNormal;
  GltfWriter w("normal" + std::to_string(variant));
  int tex = w.AddTexture(HalfAndHalf(kTiltedNormal, flat), kClamp, kClamp);
  std::string scale = variant == 2 ? ", \"scale\": 0.5" : "";
  w.AddMaterial(R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.5},
                    "normalTexture": {"index": )" + std::to_string(tex) + scale + "}}");
  GltfPrimitive sq = Square();
  if (variant == 1) sq.tangents.assign(4, vec4(1, 0, 0, 1));
  w.AddPrimitive(sq);
  std::string file = w.Write(dir);
  double d = 600.0;
  std::string light = R"(, "lights": [{"type": "point", "position": [)" +
                      std::to_string(d * std::sqrt(0.5)) + ", 0, " + std::to_string(d * std::sqrt(0.5)) +
                      R"(], "intensity": [)" + std::to_string(d * d) + ", " + std::to_string(d * d) +
                      ", " + std::to_string(d * d) + "]}]";
  return LoadGenerated(dir, spec, FarCamera(1.0),
                       R"({"type": "mesh", "file": ")" + file + "\"}", light);
}

// A square whose emissive texture is black on the left half and white on the right, factor 1
// and KHR_materials_emissive_strength 3, base colour black; with `floor`, a diffuse floor in
// front of it (and a camera that sees both) so that its light is measured by each integrator.
// alphaMode "MASK" cuts away its top half (base colour texture alpha 0 there); "BLEND" makes it
// half transparent (base colour alpha 0.5).
inline Scene EmissiveTextureScene(const std::string& dir, bool floor, const SceneSpec& spec,
                                  const std::string& alphaMode = "") {
  const uint8_t black[4] = {0, 0, 0, 255}, white[4] = {255, 255, 255, 255};
  GltfWriter w("emissive" + alphaMode);
  int tex = w.AddTexture(HalfAndHalf(black, white), kClamp, kClamp);
  std::string base = R"("baseColorFactor": [0, 0, 0, 1])", alpha;
  if (alphaMode == "MASK") {
    RgbaImage cut(1, 8);
    for (int y = 0; y < 8; ++y) cut.Set(0, y, 255, 255, 255, y < 4 ? 0 : 255);
    base += R"(, "baseColorTexture": {"index": )" + std::to_string(w.AddTexture(cut, kClamp, kClamp)) + "}";
    alpha = R"("alphaMode": "MASK", )";
  } else if (alphaMode == "BLEND") {
    base = R"("baseColorFactor": [0, 0, 0, 0.5])";
    alpha = R"("alphaMode": "BLEND", )";
  }
  w.AddMaterial("{" + alpha + R"("pbrMetallicRoughness": {)" + base + R"(, "metallicFactor": 0},
                    "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": )" +
                std::to_string(tex) + R"(},
                    "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}}})");
  w.AddPrimitive(Square());
  std::string mesh = R"({"type": "mesh", "file": ")" + w.Write(dir) + "\"}";
  if (!floor) return LoadGenerated(dir, spec, FarCamera(1.0), mesh);
  std::string floorQuad = R"(, {"type": "quad", "origin": [-3, -1.2, 0.01], "u": [0, 0, 5],
                              "v": [6, 0, 0], "material": "floor"})";
  std::string camera = R"({"position": [0, 2.5, 7], "look_at": [0, -1.2, 1.5], "fov_y": 40})";
  return LoadGenerated(dir, spec, camera, mesh + floorQuad);
}

// A diffuse floor (y = 0) under a point light at height 8, with an occluding glTF square at
// height 2 between them (x, z in [-1, 1], its u along +x). Modes: "none" (no occluder), "mask"
// (alpha 0 on the u < 0.5 half, 1 on the other, MASK 0.5, double-sided), "blend" (BLEND,
// alpha 0.5 everywhere, double-sided), "up" / "down" (opaque, single-sided, facing up or down).
// The camera (at height 1) sees the floor only; the occluder's shadow spans |x| < 4/3.
// `instanced`: the occluder placed by an instance of the scene's mesh table (identity).
inline Scene AlphaShadowScene(const std::string& dir, const std::string& mode, const SceneSpec& spec,
                              bool instanced = false) {
  std::string objects = R"({"type": "quad", "origin": [-4, 0, -4], "u": [0, 0, 8], "v": [8, 0, 0],
                            "material": "floor"})";
  std::string meshes;
  if (mode != "none") {
    GltfWriter w("occluder_" + mode);
    std::string alpha;
    if (mode == "mask") {
      const uint8_t clear[4] = {255, 255, 255, 0}, solid[4] = {255, 255, 255, 255};
      int tex = w.AddTexture(HalfAndHalf(clear, solid), kClamp, kClamp);
      alpha = R"(, "alphaMode": "MASK", "doubleSided": true, "pbrMetallicRoughness": {"baseColorTexture": {"index": )" +
              std::to_string(tex) + "}}";
    } else if (mode == "blend") {
      alpha = R"(, "alphaMode": "BLEND", "doubleSided": true, "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5]})";
    }
    w.AddMaterial("{\"name\": \"occluder\"" + alpha + "}");
    GltfPrimitive sq;
    sq.positions = {vec3(-1, 2, 1), vec3(1, 2, 1), vec3(1, 2, -1), vec3(-1, 2, -1)};  // faces +y
    sq.uvs = {vec2(0, 1), vec2(1, 1), vec2(1, 0), vec2(0, 0)};
    sq.indices = mode == "down" ? std::vector<uint32_t>{0, 2, 1, 0, 3, 2}
                                : std::vector<uint32_t>{0, 1, 2, 0, 2, 3};
    sq.material = 0;
    w.AddPrimitive(sq);
    const std::string file = w.Write(dir);
    if (instanced) meshes = R"(, "meshes": {"occluder": {"file": ")" + file + "\"}}";
    objects += instanced ? std::string(R"(, {"type": "instance", "mesh": "occluder"})")
                         : R"(, {"type": "mesh", "file": ")" + file + "\"}";
  }
  std::string camera = R"({"position": [0, 1, 6], "look_at": [0, 0, 0], "fov_y": 45})";
  return LoadGenerated(dir, spec, camera, objects,
                       meshes + R"(, "lights": [{"type": "point", "position": [0, 8, 0], "intensity": [64, 64, 64]}])");
}

// A smooth transmissive glTF in a white environment seen head-on: a thin-walled square
// (transmission 1, no volume) or, with `volume`, a 2 x 2 x 2 cube with KHR_materials_volume
// (thickness 1; attenuationColor `attenuation` at distance 2). Base colour `tint`, ior 1.5.
inline Scene TransmissionScene(const std::string& dir, bool volume, vec3 tint, float attenuation,
                               const SceneSpec& spec) {
  GltfWriter w(volume ? "cube" : "pane");
  char base[96];
  std::snprintf(base, sizeof(base), "[%.6g, %.6g, %.6g, 1]", tint.x, tint.y, tint.z);
  std::string ext = R"("KHR_materials_transmission": {"transmissionFactor": 1})";
  if (volume)
    ext += R"(, "KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": 2,
              "attenuationColor": [)" + std::to_string(attenuation) + ", " +
           std::to_string(attenuation) + ", " + std::to_string(attenuation) + "]}";
  w.AddMaterial(R"({"doubleSided": true, "pbrMetallicRoughness": {"baseColorFactor": )" +
                std::string(base) + R"(, "metallicFactor": 0, "roughnessFactor": 0},
                "extensions": {)" + ext + "}}");
  if (!volume) {
    w.AddPrimitive(Square());
  } else {
    GltfPrimitive cube;  // 8 corners, 12 outward-facing triangles
    for (int i = 0; i < 8; ++i)
      cube.positions.push_back(vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    cube.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                    2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    cube.material = 0;
    w.AddPrimitive(cube);
  }
  return LoadGenerated(dir, spec, FarCamera(0.8),
                       R"({"type": "mesh", "file": ")" + w.Write(dir) + "\"}",
                       R"(, "background": [1, 1, 1])");
}

// A smooth white glTF square with COLOR_0 `color` at every vertex, in a white environment.
inline Scene VertexColorScene(const std::string& dir, vec4 color, const SceneSpec& spec) {
  GltfWriter w("colored");
  w.AddMaterial(R"({"pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0}})");
  GltfPrimitive sq = Square();
  sq.colors.assign(4, color);
  w.AddPrimitive(sq);
  return LoadGenerated(dir, spec, FarCamera(0.9),
                       R"({"type": "mesh", "file": ")" + w.Write(dir) + "\"}",
                       R"(, "background": [1, 1, 1])");
}

// A 256 x 256 emissive checker of single black and white texels on a square that fills the
// image: each pixel covers 256 / size texels.
inline Scene DistantCheckerScene(const std::string& dir, const SceneSpec& spec) {
  RgbaImage img(256, 256);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      uint8_t c = (x + y) % 2 ? 255 : 0;
      img.Set(x, y, c, c, c, 255);
    }
  GltfWriter w("checker");
  int tex = w.AddTexture(img);
  w.AddMaterial(R"({"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                    "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": )" +
                std::to_string(tex) + "}}");
  w.AddPrimitive(Square());
  return LoadGenerated(dir, spec, FarCamera(1.0), R"({"type": "mesh", "file": ")" + w.Write(dir) + "\"}");
}

}  // namespace pt::test
