// The decoders of compressed glTF geometry (src/io/gltf_document.h uses them): meshopt buffer
// views (libmeshoptimizer) and Draco primitives (libdraco). Each throws std::runtime_error
// starting with `part`, the glTF path of what it decodes, when the data is malformed.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pt {

// The bytes of one EXT_/KHR_meshopt_compression buffer view: `ext` is the extension object
// (mode, count, byteStride, filter), data/size its compressed bytes. Returns count * byteStride
// bytes, the filter undone.
std::string DecodeMeshoptView(const nlohmann::json& ext, const unsigned char* data, size_t size,
                              const std::string& part);

// One glTF attribute of a Draco primitive, in the layout its accessor declares.
struct DracoAttributeRequest {
  std::string name;       // "POSITION", "TEXCOORD_0", ...
  int64_t uniqueId = 0;   // the extension's attribute id in the Draco data
  int componentType = 0;  // glTF component type (5120 ... 5126)
  int components = 0;     // 1 (SCALAR) to 4 (VEC4)
};

struct DracoMeshData {
  size_t points = 0;              // vertices of the decoded mesh
  std::vector<uint32_t> indices;  // three per triangle
  std::vector<std::string> values;  // per request: points x components, packed
};

// Decodes the Draco mesh in data/size and the requested attributes (each converted to its
// accessor's component type, normalisation as Draco records it).
DracoMeshData DecodeDracoMesh(const unsigned char* data, size_t size,
                              const std::vector<DracoAttributeRequest>& requests,
                              const std::string& part);

}  // namespace pt
