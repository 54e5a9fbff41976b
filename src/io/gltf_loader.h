// glTF 2.0 (.gltf and .glb) meshes: every triangle primitive of the default scene (or scene 0),
// node transforms composed, vertex normals kept, materials mapped to the renderer's.
#pragma once

#include <string>
#include <vector>

#include "src/io/mesh_common.h"

namespace tinygltf {
struct Material;
}

namespace pt {

// Loads the file's triangles into the sink (its materials too, unless the sink overrides them).
// Throws std::runtime_error for an unreadable or malformed file.
void LoadGltfMesh(const std::string& path, MeshSink& sink);

// A glTF material as the scene format maps it, with the approximations made (each a phrase for
// the warning: rough to smooth, plastic to diffuse, textures ignored, ...).
struct MappedGltfMaterial {
  Material material;
  std::vector<std::string> approximations;
};
MappedGltfMaterial MapGltfMaterial(const tinygltf::Material& material);

}  // namespace pt
