// Writes small glTF files for the material tests: primitives with any of the per-vertex
// attributes (NORMAL, TEXCOORD_0/1, TANGENT, COLOR_0), PNG images, textures, samplers and
// materials given as JSON. dir/NAME.gltf + NAME.bin + NAME_imageN.png.
#pragma once

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>
#include <vector>

#include "src/core/math.h"
#include "tests/texture_test_util.h"

namespace pt::test {

struct GltfPrimitive {
  std::vector<vec3> positions, normals;
  std::vector<vec2> uvs, uvs1;
  std::vector<vec4> tangents, colors;
  std::vector<uint32_t> indices;  // empty: non-indexed
  int material = -1;
};

// The square [-h, h]^2 at height z facing +z (two triangles), UVs with the image upright seen
// from +z: uv (0, 0) at the corner (-h, h).
inline GltfPrimitive Square(float h = 1.0f, float z = 0.0f, int material = 0) {
  GltfPrimitive p;
  p.positions = {vec3(-h, -h, z), vec3(h, -h, z), vec3(h, h, z), vec3(-h, h, z)};
  p.normals.assign(4, vec3(0, 0, 1));
  p.uvs = {vec2(0, 1), vec2(1, 1), vec2(1, 0), vec2(0, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = material;
  return p;
}

class GltfWriter {
 public:
  using Json = nlohmann::json;

  explicit GltfWriter(std::string name) : name_(std::move(name)) {}

  // An image (written as PNG on Write) and a texture reading it; returns the texture index.
  int AddTexture(const RgbaImage& image, int wrapS = 10497, int wrapT = 10497) {
    images_.push_back(image);
    samplers_.push_back({{"wrapS", wrapS}, {"wrapT", wrapT}});
    textures_.push_back({{"source", int(images_.size()) - 1}, {"sampler", int(samplers_.size()) - 1}});
    return int(textures_.size()) - 1;
  }
  int AddMaterial(const std::string& json) {
    materials_.push_back(Json::parse(json));
    return int(materials_.size()) - 1;
  }
  void AddPrimitive(const GltfPrimitive& p) { primitives_.push_back(p); }

  // Writes dir/NAME.gltf and its buffer and images; returns the .gltf's file name.
  std::string Write(const std::string& dir) {
    Json prims = Json::array();
    for (const GltfPrimitive& p : primitives_) prims.push_back(Primitive(p));
    Json images = Json::array();
    for (size_t i = 0; i < images_.size(); ++i) {
      std::string file = name_ + "_image" + std::to_string(i) + ".png";
      WriteFile(dir + "/" + file, EncodePng(images_[i]));
      images.push_back({{"uri", file}});
    }
    Json doc = {{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0}}}}},
                {"nodes", {{{"mesh", 0}}}},
                {"meshes", {{{"primitives", prims}}}},
                {"accessors", accessors_},
                {"bufferViews", views_},
                {"buffers", {{{"uri", name_ + ".bin"}, {"byteLength", bin_.size()}}}}};
    if (!materials_.empty()) doc["materials"] = materials_;
    if (!textures_.empty()) {
      doc["textures"] = textures_;
      doc["samplers"] = samplers_;
      doc["images"] = images;
    }
    if (!extensionsUsed_.empty()) doc["extensionsUsed"] = extensionsUsed_;
    WriteFile(dir + "/" + name_ + ".bin", bin_);
    std::ofstream(dir + "/" + name_ + ".gltf") << doc.dump(1);
    return name_ + ".gltf";
  }

  void UseExtension(const std::string& name) { extensionsUsed_.push_back(name); }

 private:
  template <typename T>
  int Accessor(const std::vector<T>& values, int componentType, const char* type, int components) {
    while (bin_.size() % 4) bin_.push_back('\0');
    size_t offset = bin_.size();
    AppendBytes(bin_, values.data(), values.size());
    views_.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bin_.size() - offset}});
    Json a = {{"bufferView", int(views_.size()) - 1}, {"componentType", componentType},
              {"count", values.size()}, {"type", type}};
    if (std::string(type) == "VEC3" && components == 3 && componentType == 5126 && !minMax_.empty()) {
      a["min"] = minMax_[0];
      a["max"] = minMax_[1];
      minMax_.clear();
    }
    accessors_.push_back(a);
    return int(accessors_.size()) - 1;
  }

  Json Primitive(const GltfPrimitive& p) {
    vec3 lo(INFINITY), hi(-INFINITY);
    for (vec3 v : p.positions) lo = glm::min(lo, v), hi = glm::max(hi, v);
    minMax_ = {{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
    Json attributes = {{"POSITION", Accessor(p.positions, 5126, "VEC3", 3)}};
    if (!p.normals.empty()) attributes["NORMAL"] = Accessor(p.normals, 5126, "VEC3", 3);
    if (!p.uvs.empty()) attributes["TEXCOORD_0"] = Accessor(p.uvs, 5126, "VEC2", 2);
    if (!p.uvs1.empty()) attributes["TEXCOORD_1"] = Accessor(p.uvs1, 5126, "VEC2", 2);
    if (!p.tangents.empty()) attributes["TANGENT"] = Accessor(p.tangents, 5126, "VEC4", 4);
    if (!p.colors.empty()) attributes["COLOR_0"] = Accessor(p.colors, 5126, "VEC4", 4);
    Json prim = {{"attributes", attributes}};
    if (!p.indices.empty()) prim["indices"] = Accessor(p.indices, 5125, "SCALAR", 1);
    if (p.material >= 0) prim["material"] = p.material;
    return prim;
  }

  std::string name_;
  std::string bin_;
  Json accessors_ = Json::array(), views_ = Json::array(), materials_ = Json::array();
  Json textures_ = Json::array(), samplers_ = Json::array();
  Json extensionsUsed_ = Json::array();
  std::vector<RgbaImage> images_;
  std::vector<std::vector<float>> minMax_;
  std::vector<GltfPrimitive> primitives_;
};

}  // namespace pt::test
