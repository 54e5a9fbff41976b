#include "src/io/gltf_nodes.h"

#include <tiny_gltf.h>

#include <stdexcept>
#include <string>

namespace pt {

glm::dmat4 GltfLocalMatrix(const tinygltf::Node& node) {
  glm::dmat4 m(1.0);
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = node.matrix[i];  // both column-major
    return m;
  }
  glm::dmat3 r(1.0);
  if (node.rotation.size() == 4) {
    glm::dvec4 q(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]);
    double len = glm::length(q);
    if (len > 0.0) q /= len;
    double x = q.x, y = q.y, z = q.z, w = q.w;
    r = glm::dmat3(glm::dvec3(1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)),
                   glm::dvec3(2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)),
                   glm::dvec3(2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)));
  }
  glm::dvec3 s(1.0);
  if (node.scale.size() == 3) s = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
  for (int c = 0; c < 3; ++c) m[c] = glm::dvec4(r[c] * s[c], 0.0);
  if (node.translation.size() == 3) {
    m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  }
  return m;
}

std::vector<int> GltfRootNodes(const tinygltf::Model& model) {
  if (!model.scenes.empty()) {
    int scene = (model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size())
                    ? model.defaultScene : 0;
    return model.scenes[scene].nodes;
  }
  // No scenes: every node that is nobody's child.
  std::vector<bool> isChild(model.nodes.size(), false);
  for (const tinygltf::Node& n : model.nodes) {
    for (int c : n.children) {
      if (c >= 0 && size_t(c) < isChild.size()) isChild[c] = true;
    }
  }
  std::vector<int> roots;
  for (size_t i = 0; i < model.nodes.size(); ++i) {
    if (!isChild[i]) roots.push_back(int(i));
  }
  return roots;
}

std::vector<glm::dmat4> GltfNodeWorldMatrices(const tinygltf::Model& model) {
  size_t n = model.nodes.size();
  std::vector<int> parent(n, -1);
  for (size_t i = 0; i < n; ++i) {
    for (int c : model.nodes[i].children) {
      if (c >= 0 && size_t(c) < n) parent[size_t(c)] = int(i);
    }
  }
  std::vector<glm::dmat4> world(n);
  std::vector<bool> done(n, false);
  for (size_t i = 0; i < n; ++i) {
    std::vector<size_t> chain;  // i and its ancestors not yet done, nearest first
    for (int k = int(i); k >= 0 && !done[size_t(k)]; k = parent[size_t(k)]) {
      chain.push_back(size_t(k));
      if (chain.size() > size_t(kMaxGltfNodeDepth)) {
        throw std::runtime_error("the node hierarchy is cyclic or too deep");
      }
    }
    for (size_t j = chain.size(); j-- > 0;) {
      size_t k = chain[j];
      int p = parent[k];
      world[k] = (p >= 0 ? world[size_t(p)] : glm::dmat4(1.0)) * GltfLocalMatrix(model.nodes[k]);
      done[k] = true;
    }
  }
  return world;
}

const tinygltf::Node& GltfNodeAt(const tinygltf::Model& model, int index, int depth) {
  if (index < 0 || size_t(index) >= model.nodes.size()) {
    throw std::runtime_error("node " + std::to_string(index) +
                             " does not exist (a scene's nodes or a node's children name it)");
  }
  if (depth > kMaxGltfNodeDepth) {
    throw std::runtime_error("the node hierarchy is cyclic or too deep");
  }
  return model.nodes[index];
}

}  // namespace pt
