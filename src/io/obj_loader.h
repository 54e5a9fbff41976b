// Wavefront OBJ meshes (tinyobjloader): faces triangulated, vertex normals kept when present,
// .mtl materials mapped (Kd -> diffuse albedo, Ke -> emissive) unless the sink overrides them.
#pragma once

#include <string>

#include "src/io/mesh_common.h"

namespace pt {

// Throws std::runtime_error for an unreadable or malformed file.
void LoadObjMesh(const std::string& path, MeshSink& sink);

}  // namespace pt
