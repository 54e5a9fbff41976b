// Writes small glTF scenes for the scene tests: triangle meshes, nodes with transforms, cameras
// and KHR_lights_punctual lights, written as dir/NAME.gltf + NAME.bin or as one dir/NAME.glb.
// The glTF document is open JSON (doc) so a test can add or break any part of it.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "src/core/math.h"

namespace pt::test {

constexpr double kDeg = 3.14159265358979323846 / 180.0;  // radians per degree

// A node's "rotation": `degrees` about the unit `axis`, a quaternion in glTF's order x, y, z, w.
inline nlohmann::json GltfRotation(double degrees, glm::dvec3 axis) {
  double h = 0.5 * degrees * kDeg;
  return {axis.x * std::sin(h), axis.y * std::sin(h), axis.z * std::sin(h), std::cos(h)};
}

class GltfSceneWriter {
 public:
  using Json = nlohmann::json;

  Json doc = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", Json::array()}}}},
              {"nodes", Json::array()}, {"meshes", Json::array()}, {"accessors", Json::array()},
              {"bufferViews", Json::array()}};

  // A mesh of one indexed triangle primitive (material -1: none); returns its index.
  int AddMesh(const std::vector<vec3>& positions, const std::vector<uint32_t>& indices,
              int material = -1) {
    vec3 lo(INFINITY), hi(-INFINITY);
    for (vec3 p : positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    Json prim = {{"attributes", {{"POSITION", Accessor(positions.data(), positions.size(), 12,
                                                       5126, "VEC3")}}},
                 {"indices", Accessor(indices.data(), indices.size(), 4, 5125, "SCALAR")}};
    doc["accessors"][prim["attributes"]["POSITION"].get<int>()]["min"] = {lo.x, lo.y, lo.z};
    doc["accessors"][prim["attributes"]["POSITION"].get<int>()]["max"] = {hi.x, hi.y, hi.z};
    if (material >= 0) prim["material"] = material;
    doc["meshes"].push_back({{"primitives", {prim}}});
    return int(doc["meshes"].size()) - 1;
  }

  // The square [-h, h] x [-h, h] in the xz plane at height y, facing +y.
  int AddFloor(float h, float y = 0.0f, int material = -1) {
    return AddMesh({vec3(-h, y, -h), vec3(-h, y, h), vec3(h, y, h), vec3(h, y, -h)},
                   {0, 1, 2, 0, 2, 3}, material);
  }

  // A node (JSON: "mesh", "camera", "translation", "children", ...); root: listed in scene 0.
  int AddNode(Json node, bool root = true) {
    doc["nodes"].push_back(std::move(node));
    int index = int(doc["nodes"].size()) - 1;
    if (root) doc["scenes"][0]["nodes"].push_back(index);
    return index;
  }

  int AddCamera(Json camera) {
    doc["cameras"].push_back(std::move(camera));
    return int(doc["cameras"].size()) - 1;
  }
  static Json Perspective(double yfov, double aspectRatio = 0.0, const std::string& name = "") {
    Json p = {{"yfov", yfov}, {"znear", 0.01}};
    if (aspectRatio > 0.0) p["aspectRatio"] = aspectRatio;
    Json c = {{"type", "perspective"}, {"perspective", p}};
    if (!name.empty()) c["name"] = name;
    return c;
  }

  // A KHR_lights_punctual light; returns its index (place it with LightNode).
  int AddLight(Json light) {
    Json& ext = doc["extensions"]["KHR_lights_punctual"]["lights"];
    ext.push_back(std::move(light));
    Json& used = doc["extensionsUsed"];
    if (std::find(used.begin(), used.end(), "KHR_lights_punctual") == used.end()) {
      used.push_back("KHR_lights_punctual");
    }
    return int(ext.size()) - 1;
  }
  static Json LightNode(int light, Json node = Json::object()) {
    node["extensions"]["KHR_lights_punctual"]["light"] = light;
    return node;
  }

  // Raw bytes as a new buffer view (4-byte aligned); returns its index.
  int AddView(const std::string& bytes) {
    while (bin_.size() % 4) bin_ += '\0';
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}});
    bin_ += bytes;
    return int(doc["bufferViews"].size()) - 1;
  }
  // An accessor of `count` elements of elementSize bytes (componentType 5126 float, 5125
  // uint32, ...; type "VEC3", "SCALAR", "MAT4", ...) over a new view of them; returns its index.
  int AddAccessor(const void* data, size_t count, size_t elementSize, int componentType,
                  const char* type) {
    while (bin_.size() % 4) bin_ += '\0';
    return Accessor(data, count, elementSize, componentType, type);
  }
  const std::string& Bin() const { return bin_; }

  // dir/NAME.gltf + NAME.bin, or dir/NAME.glb; returns the path.
  std::string Write(const std::string& dir, const std::string& name, bool glb = false) {
    Json d = doc;
    if (glb) {
      d["buffers"] = {{{"byteLength", bin_.size()}}};
      std::string json = d.dump();
      while (json.size() % 4) json += ' ';
      std::string bin = bin_;
      while (bin.size() % 4) bin += '\0';
      std::string out;
      uint32_t total = uint32_t(12 + 8 + json.size() + 8 + bin.size());
      Put(out, 0x46546C67u), Put(out, 2u), Put(out, total);
      Put(out, uint32_t(json.size())), Put(out, 0x4E4F534Au), out += json;
      Put(out, uint32_t(bin.size())), Put(out, 0x004E4942u), out += bin;
      std::ofstream(dir + "/" + name + ".glb", std::ios::binary) << out;
      return dir + "/" + name + ".glb";
    }
    d["buffers"] = {{{"uri", name + ".bin"}, {"byteLength", bin_.size()}}};
    std::ofstream(dir + "/" + name + ".bin", std::ios::binary) << bin_;
    std::ofstream(dir + "/" + name + ".gltf") << d.dump(1);
    return dir + "/" + name + ".gltf";
  }

 private:
  static void Put(std::string& out, uint32_t v) {
    out.append(reinterpret_cast<const char*>(&v), 4);  // GLB is little-endian, as the host
  }

  int Accessor(const void* data, size_t count, size_t elementSize, int componentType,
               const char* type) {
    size_t offset = bin_.size();
    bin_.append(static_cast<const char*>(data), count * elementSize);
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", count * elementSize}});
    doc["accessors"].push_back({{"bufferView", int(doc["bufferViews"].size()) - 1},
                                {"componentType", componentType}, {"count", count}, {"type", type}});
    return int(doc["accessors"].size()) - 1;
  }

  std::string bin_;
};

}  // namespace pt::test
