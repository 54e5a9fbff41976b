// glTF 2.0 (.gltf and .glb) meshes: every triangle primitive of the default scene (or scene 0),
// node transforms composed, vertex normals kept, and the per-vertex data (TEXCOORD_0/1,
// TANGENT, COLOR_0) that the primitive's material reads; materials mapped by gltf_material.h
// (textures decoded only when a used material needs them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/io/mesh_common.h"

namespace pt {

// Loads the file's triangles into the sink (its materials too, unless the sink overrides them).
// Throws std::runtime_error for an unreadable or malformed file.
void LoadGltfMesh(const std::string& path, MeshSink& sink);

}  // namespace pt
