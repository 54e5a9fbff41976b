#include "src/io/gltf_variants.h"

#include <tiny_gltf.h>

#include <vector>

namespace pt {
namespace {

// The names of the file's variants (root extension), in order.
std::vector<std::string> VariantNames(const tinygltf::Model& model) {
  std::vector<std::string> names;
  auto it = model.extensions.find("KHR_materials_variants");
  if (it == model.extensions.end() || !it->second.IsObject() || !it->second.Has("variants"))
    return names;
  const tinygltf::Value& list = it->second.Get("variants");
  if (!list.IsArray()) return names;
  for (size_t i = 0; i < list.ArrayLen(); ++i) {
    const tinygltf::Value& v = list.Get(int(i));
    bool named = v.IsObject() && v.Has("name") && v.Get("name").IsString();
    names.push_back(named ? v.Get("name").Get<std::string>() : "");
  }
  return names;
}

}  // namespace

int GltfVariantIndex(const tinygltf::Model& model, const std::string& name) {
  if (name.empty()) return -1;
  std::vector<std::string> names = VariantNames(model);
  std::string list;
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return int(i);
    list.append(list.empty() ? "" : ", ").append("\"").append(names[i]).append("\"");
  }
  if (names.empty())
    throw GltfVariantError("no material variant \"" + name +
                           "\": the file defines none (no KHR_materials_variants)");
  throw GltfVariantError("no material variant \"" + name + "\" (the file's variants: " + list + ")");
}

int GltfVariantMaterial(const tinygltf::Primitive& p, int variant) {
  if (variant < 0) return p.material;
  auto it = p.extensions.find("KHR_materials_variants");
  if (it == p.extensions.end() || !it->second.IsObject() || !it->second.Has("mappings"))
    return p.material;
  const tinygltf::Value& mappings = it->second.Get("mappings");
  if (!mappings.IsArray()) return p.material;
  for (size_t i = 0; i < mappings.ArrayLen(); ++i) {
    const tinygltf::Value& m = mappings.Get(int(i));
    if (!m.IsObject() || !m.Has("material") || !m.Get("material").IsInt() || !m.Has("variants"))
      continue;
    const tinygltf::Value& variants = m.Get("variants");
    if (!variants.IsArray()) continue;
    for (size_t k = 0; k < variants.ArrayLen(); ++k) {
      const tinygltf::Value& v = variants.Get(int(k));
      if (v.IsInt() && v.GetNumberAsInt() == variant) return m.Get("material").GetNumberAsInt();
    }
  }
  return p.material;
}

}  // namespace pt
