// The glTF node hierarchy, shared by the mesh loader and the reader of cameras and lights:
// a node's local matrix, the default scene's root nodes, and the depth bound of a walk.
#pragma once

#include <vector>

#include "src/core/math.h"

namespace tinygltf {
class Model;
class Node;
}  // namespace tinygltf

namespace pt {

constexpr int kMaxGltfNodeDepth = 256;  // deeper is a cycle (glTF forbids them) or abuse

// The node's matrix, or T * R * S of its translation, rotation (a unit quaternion, normalised
// here) and scale, in double precision.
glm::dmat4 GltfLocalMatrix(const tinygltf::Node& node);

// Node `index` of a walk at `depth`; throws std::runtime_error when it does not exist or the
// walk is deeper than kMaxGltfNodeDepth.
const tinygltf::Node& GltfNodeAt(const tinygltf::Model& model, int index, int depth);

// The root nodes of the default scene (scene 0 when none is named); without scenes, every
// node that is nobody's child.
std::vector<int> GltfRootNodes(const tinygltf::Model& model);

}  // namespace pt
