// Reading glTF accessors: any component type (normalised or not) as doubles, sparse
// substitution applied, every byte range bounds checked; the typed readers the mesh, skin and
// animation loaders use. Each throws std::runtime_error ("accessor 7 does not exist", "buffer
// view 2 is read past its end") for malformed data.
#pragma once

#include <cstdint>
#include <vector>

#include "src/core/math.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace pt {

// Every element of accessor `index`, `components` values each (its type must have that many:
// 1 SCALAR ... 4 VEC4, 16 MAT4).
std::vector<double> ReadAccessor(const tinygltf::Model& model, int index, int components);

std::vector<vec3> ReadVec3s(const tinygltf::Model& model, int index);
// TEXCOORD_n: float, or normalized unsigned byte/short (normalization applied when reading).
std::vector<vec2> ReadVec2s(const tinygltf::Model& model, int index);
// TANGENT: four floats (xyz and the bitangent sign w).
std::vector<vec4> ReadTangents(const tinygltf::Model& model, int index);
// COLOR_0: VEC3 or VEC4, linear, clamped to [0, 1]; RGB gets alpha 1.
std::vector<vec4> ReadColors(const tinygltf::Model& model, int index);

// Vertex indices of the primitive's triangles (lists, strips and fans), three per triangle, in
// glTF winding; checked against vertexCount.
std::vector<uint32_t> TriangleIndices(const tinygltf::Model& model, const tinygltf::Primitive& p,
                                      size_t vertexCount);

}  // namespace pt
