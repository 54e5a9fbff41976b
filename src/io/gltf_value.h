// Reading optional fields of a glTF extension object (tinygltf::Value) with a fallback where a
// field is absent or of the wrong type: shared by the core material reader and the material
// extensions' reader (src/io/gltf_material*.cpp).
#pragma once

#include <tiny_gltf.h>

#include "src/core/math.h"

namespace pt {

// The extension object called name, or null when absent or not an object.
inline const tinygltf::Value* GltfExtension(const tinygltf::ExtensionMap& extensions,
                                            const char* name) {
  auto it = extensions.find(name);
  return (it == extensions.end() || !it->second.IsObject()) ? nullptr : &it->second;
}

// A number field, or fallback when absent or not a number.
inline double GltfNumber(const tinygltf::Value* ext, const char* key, double fallback) {
  if (!ext || !ext->Has(key)) return fallback;
  const tinygltf::Value& v = ext->Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// A 3-number array field, or fallback when absent, short or holding a non-number.
inline vec3 GltfVec3(const tinygltf::Value* ext, const char* key, vec3 fallback) {
  if (!ext || !ext->Has(key)) return fallback;
  const tinygltf::Value& v = ext->Get(key);
  if (!v.IsArray() || v.ArrayLen() < 3) return fallback;
  vec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v.Get(i).IsNumber()) return fallback;
    out[i] = float(v.Get(i).GetNumberAsDouble());
  }
  return out;
}

}  // namespace pt
