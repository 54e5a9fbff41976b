// KHR_materials_variants: a file's named material variants, and the material each primitive
// shows in one of them (its mapping for that variant, else its own material).
#pragma once

#include <stdexcept>
#include <string>

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace pt {

// An unknown variant name: the message lists the variants the file has. The loaders turn it
// into an error naming the file and the field that asked for it (--variant, "variant").
struct GltfVariantError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The index of variant `name` among the file's variants; -1 for an empty name (none asked).
// Throws GltfVariantError when the file has no such variant.
int GltfVariantIndex(const tinygltf::Model& model, const std::string& name);

// The material primitive p shows in variant `variant` (-1: its own material).
int GltfVariantMaterial(const tinygltf::Primitive& p, int variant);

}  // namespace pt
