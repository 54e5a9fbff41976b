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

// Every node's world matrix (its parents' local matrices composed with its own; a node nobody
// names as a child is a root), in the file's space. Skins read their joints' from it. Throws
// std::runtime_error for a cyclic or too deep hierarchy.
std::vector<glm::dmat4> GltfNodeWorldMatrices(const tinygltf::Model& model);

// The root nodes of the default scene (scene 0 when none is named); without scenes, every
// node that is nobody's child.
std::vector<int> GltfRootNodes(const tinygltf::Model& model);

}  // namespace pt
