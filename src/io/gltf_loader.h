// glTF 2.0 (.gltf and .glb) meshes: every triangle primitive of the default scene (or scene 0),
// node transforms composed, vertex normals and TEXCOORD_0 kept, materials mapped to the
// renderer's with their base colour textures (decoded only when a used material needs them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/io/gltf_scene.h"
#include "src/io/mesh_common.h"

namespace tinygltf {
struct Material;
class Model;
}  // namespace tinygltf

namespace pt {

// Loads the file's triangles into the sink (its materials too, unless the sink overrides them)
// and returns its cameras, lights and ignored parts (src/io/gltf_scene.h), placed by the
// sink's object transform. Throws std::runtime_error for an unreadable or malformed file.
GltfSceneContents LoadGltfMesh(const std::string& path, MeshSink& sink);

// The cameras, lights and ignored parts alone (no triangles), in the file's own space.
GltfSceneContents ReadGltfSceneParts(const std::string& path);

// A glTF material as the scene format maps it, with the glTF features it cannot honour (each a
// phrase for the warning: "normalTexture ignored", ...). Textures are resolved separately.
struct MappedGltfMaterial {
  Material material;
  std::vector<std::string> approximations;
};
MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& material);

// The sRGB EOTF (IEC 61966-2-1): an encoded value in [0, 1] to linear, computed in double.
double SrgbToLinear(double encoded);
// The same for an 8-bit code, exact to float rounding (a table of the 256 values).
float Srgb8ToLinear(uint8_t code);

// Encoded bytes of images given by URI (data: or a file), captured while tinygltf parses and
// indexed by image; images in buffer views are read from their view when needed.
using GltfEncodedImages = std::vector<std::vector<unsigned char>>;

// Scene materials for a model's glTF materials, added on first use with a warning that names
// the material and what it cannot honour; base colour textures decoded then, once per image.
class GltfMaterialTable {
 public:
  GltfMaterialTable(const tinygltf::Model& model, const GltfEncodedImages& images, MeshSink& sink);

  // The scene material for glTF material index (-1: the glTF default material).
  uint32_t Index(int material);
  // Whether that material (already added by Index) has a base colour texture.
  bool Textured(int material) const;
  // "material \"name\" (#3)" or "default material", for warnings.
  std::string DisplayName(int material) const;

 private:
  int32_t BaseColorTexture(int texture, std::vector<std::string>& notes);
  int32_t ImageTexels(int image, TextureWrap wrapS, TextureWrap wrapT);

  const tinygltf::Model& model_;
  const GltfEncodedImages& images_;
  MeshSink& sink_;
  std::vector<int64_t> materials_;   // scene index per glTF material, -1 until used
  std::vector<bool> textured_;
  int64_t defaultMaterial_ = -1;
  std::vector<int64_t> textures_;    // scene texture per glTF texture, -1 unused, -2 unusable
  std::vector<int64_t> imageTextures_;  // scene texture holding an image's texels, or -1/-2
};

}  // namespace pt
