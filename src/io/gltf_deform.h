// Skins and morph targets of glTF meshes. The renderer stores triangles, so a skinned or
// morphed mesh is deformed at load, in the pose of the nodes (the file's static pose, or the
// one an animation set: src/io/gltf_animation.h), and placed in world space once per node.
#pragma once

#include <vector>

#include "src/core/math.h"

namespace tinygltf {
class Model;
class Node;
struct Primitive;
}  // namespace tinygltf

namespace pt {

// One primitive's vertex data that deforms (empty arrays: the primitive lacks them).
struct GltfVertices {
  std::vector<vec3> positions, normals;
  std::vector<vec4> tangents;  // xyz and the bitangent sign w
};

// The morph weights of a node's mesh: the node's "weights", else the mesh's, as many as the
// mesh has targets (missing ones 0). Empty when the mesh has no targets.
std::vector<double> GltfMorphWeights(const tinygltf::Model& model, const tinygltf::Node& node);

// Adds the primitive's targets' POSITION, NORMAL and TANGENT deltas times their weights (then
// normals and tangents renormalised). Throws std::runtime_error naming the target for a
// malformed one.
void ApplyGltfMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& p,
                           const std::vector<double>& weights, GltfVertices& v);

// Skin `skin`'s joint matrices (each joint's world matrix times its inverse bind matrix), in the
// file's world space. Throws naming "skins[N]..." for a missing joint, or fewer inverse bind
// matrices than joints.
std::vector<glm::dmat4> GltfJointMatrices(const tinygltf::Model& model, int skin,
                                          const std::vector<glm::dmat4>& nodeWorld);

// Skins the vertices by JOINTS_0/WEIGHTS_0 (and JOINTS_1/WEIGHTS_1: up to 8 influences; weights
// normalised to sum 1) into world space: positions by the blended matrix, normals by its
// inverse transpose, tangents by it. A vertex without weight keeps `meshWorld`. Throws for a
// joint index outside the skin or missing attributes.
void ApplyGltfSkin(const tinygltf::Model& model, const tinygltf::Primitive& p,
                   const std::vector<glm::dmat4>& joints, const glm::dmat4& meshWorld,
                   GltfVertices& v);

}  // namespace pt
