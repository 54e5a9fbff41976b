// glTF materials as the renderer's: the metallic-roughness material with its textures and
// extensions mapped to MaterialType::kGltfPbr (src/materials/gltf_pbr.h), images decoded on
// first use into RGBA8 mip pyramids, and what cannot be honoured collected into one summary
// warning per file ("materials: occlusionTexture ignored (3 materials), ...").
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "src/io/mesh_common.h"

namespace tinygltf {
struct Material;
class Model;
class Value;
}  // namespace tinygltf

namespace pt {

// A glTF material's factors and extensions (textures are resolved by GltfMaterialTable), with
// what the renderer cannot honour, each a phrase for the summary ("occlusionTexture ignored").
struct MappedGltfMaterial {
  Material material;
  GltfMaterialExtension extension;  // mask 0: none (textures resolved by GltfMaterialTable)
  std::vector<std::string> approximations;
};
MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& material);

// The extensions of the layered BSDF (gltf_material_ext.cpp): whether `name` is one, and a
// material's factors of them (mask bits only for extensions with an effect).
bool LayeredGltfExtension(const std::string& name);
GltfMaterialExtension MapGltfExtensions(const tinygltf::Material& material,
                                        std::vector<std::string>& notes);

// The previous mapping onto the plain materials (conductor for metallic >= 0.5, plastic below,
// dielectric when transmissive, emissive when emitting; base colour texture only), kept to
// measure what the full material costs: PT_GLTF_MATERIALS=legacy selects it.
MappedGltfMaterial MapGltfMaterialLegacy(const tinygltf::Material& material);
bool UseLegacyGltfMaterials();

// Encoded bytes of images given by URI (data: or a file), captured while tinygltf parses and
// indexed by image; images in buffer views are read from their view when needed.
using GltfEncodedImages = std::vector<std::vector<unsigned char>>;

// What a material's lookups read per vertex.
struct GltfVertexNeeds {
  bool uv[2] = {false, false};  // TEXCOORD_0, TEXCOORD_1
  bool tangents = false;        // TANGENT (a normal texture)
  bool colors = false;          // COLOR_0 (glTF materials multiply base colour by it)
};

// Scene materials for a model's glTF materials, added on first use; textures decoded then,
// once per image and colour space. Finish() warns once for the whole file.
class GltfMaterialTable {
 public:
  GltfMaterialTable(const tinygltf::Model& model, const GltfEncodedImages& images, MeshSink& sink);

  // The scene material for glTF material index (-1: the glTF default material).
  uint32_t Index(int material);
  // What that material (already added by Index) reads per vertex.
  GltfVertexNeeds Needs(int material) const;
  // Records something the renderer does not honour, for the summary (per material counted).
  void Note(const std::string& what, int material);
  // The summary warning, if any note was recorded.
  void Finish();

 private:
  // A texture slot: its glTF texture, UV set and KHR_texture_transform; -1 when unusable.
  struct Slot {
    int texture = -1;
    int texCoord = 0;
    const tinygltf::Value* transform = nullptr;  // the KHR_texture_transform object, or null
  };
  int32_t AddSlot(const Slot& slot, bool srgb, const char* name, int material);
  static Slot SlotIn(const tinygltf::Value* extension, const char* key);
  void ResolveExtensionTextures(const tinygltf::Material& source, int material,
                                GltfMaterialExtension& e);
  int32_t SceneTexture(int texture, bool srgb, int material);
  int32_t ImageTexels(int image, bool srgb, TextureWrap wrapS, TextureWrap wrapT, int material);
  void ResolveTextures(const tinygltf::Material& source, int material, Material& m);

  const tinygltf::Model& model_;
  const GltfEncodedImages& images_;
  MeshSink& sink_;
  std::vector<int64_t> materials_;  // scene index per glTF material, -1 until used
  int64_t defaultMaterial_ = -1;
  std::vector<GltfVertexNeeds> needs_;  // per glTF material, the default last
  std::map<std::pair<int, bool>, int32_t> textures_;     // (texture, srgb) -> scene texture
  std::map<std::pair<int, bool>, int32_t> imageTexels_;  // (image, srgb) -> scene texture
  std::map<std::string, std::set<int>> notes_;          // note -> materials (-1 default)
  std::set<int> colored_;  // materials of primitives with COLOR_0 (-1: the default)
};

}  // namespace pt
