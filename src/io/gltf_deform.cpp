#include "src/io/gltf_deform.h"

#include <tiny_gltf.h>

#include <stdexcept>
#include <string>

#include "src/io/gltf_accessors.h"

namespace pt {
namespace {

[[noreturn]] void DeformFail(const std::string& what) { throw std::runtime_error(what); }

vec3 NormalizedOr(vec3 v, vec3 fallback) {
  float len = glm::length(v);
  return len > 0.0f && std::isfinite(len) ? v / len : fallback;
}

// An attribute's values, checked to be one per vertex.
std::vector<double> PerVertex(const tinygltf::Model& model, const tinygltf::Primitive& p,
                              const std::string& name, int components, size_t count) {
  auto it = p.attributes.find(name);
  if (it == p.attributes.end()) return {};
  std::vector<double> values = ReadAccessor(model, it->second, components);
  if (values.size() != count * size_t(components)) DeformFail(name + " and POSITION counts differ");
  return values;
}

}  // namespace

std::vector<double> GltfMorphWeights(const tinygltf::Model& model, const tinygltf::Node& node) {
  const tinygltf::Mesh& mesh = model.meshes[size_t(node.mesh)];
  size_t targets = 0;
  for (const tinygltf::Primitive& p : mesh.primitives) targets = std::max(targets, p.targets.size());
  std::vector<double> w = !node.weights.empty() ? node.weights : mesh.weights;
  w.resize(targets, 0.0);
  return w;
}

void ApplyGltfMorphTargets(const tinygltf::Model& model, const tinygltf::Primitive& p,
                           const std::vector<double>& weights, GltfVertices& v) {
  size_t n = v.positions.size();
  for (size_t k = 0; k < p.targets.size() && k < weights.size(); ++k) {
    double w = weights[k];
    if (w == 0.0) continue;
    std::string part = "targets[" + std::to_string(k) + "].";
    for (const auto& [name, accessor] : p.targets[k]) {
      bool position = name == "POSITION", normal = name == "NORMAL", tangent = name == "TANGENT";
      if (!(position && n) && !(normal && !v.normals.empty()) && !(tangent && !v.tangents.empty())) {
        continue;  // an attribute the primitive does not keep
      }
      std::vector<vec3> delta;
      try {
        delta = ReadVec3s(model, accessor);
      } catch (const std::runtime_error& e) {
        DeformFail(part + name + ": " + e.what());
      }
      if (delta.size() != n) DeformFail(part + name + ": its count differs from POSITION's");
      for (size_t i = 0; i < n; ++i) {
        vec3 d = float(w) * delta[i];
        if (position) v.positions[i] += d;
        if (normal) v.normals[i] += d;
        if (tangent) v.tangents[i] += vec4(d, 0.0f);
      }
    }
  }
  for (vec3& nrm : v.normals) nrm = NormalizedOr(nrm, nrm);
  for (vec4& t : v.tangents) t = vec4(NormalizedOr(vec3(t), vec3(t)), t.w);
}

std::vector<glm::dmat4> GltfJointMatrices(const tinygltf::Model& model, int skin,
                                          const std::vector<glm::dmat4>& nodeWorld) {
  std::string part = "skins[" + std::to_string(skin) + "]";
  if (skin < 0 || size_t(skin) >= model.skins.size()) DeformFail(part + " does not exist");
  const tinygltf::Skin& s = model.skins[size_t(skin)];
  if (s.joints.empty()) DeformFail(part + ".joints: a skin needs joints");
  std::vector<double> inverseBind;
  if (s.inverseBindMatrices >= 0) {
    try {
      inverseBind = ReadAccessor(model, s.inverseBindMatrices, 16);
    } catch (const std::runtime_error& e) {
      DeformFail(part + ".inverseBindMatrices: " + e.what());
    }
    if (inverseBind.size() / 16 < s.joints.size()) {
      DeformFail(part + ".inverseBindMatrices: accessor " + std::to_string(s.inverseBindMatrices) +
                 " holds " + std::to_string(inverseBind.size() / 16) +
                 (inverseBind.size() / 16 == 1 ? " matrix" : " matrices") + " for " +
                 std::to_string(s.joints.size()) + " joints");
    }
  }
  std::vector<glm::dmat4> joints;
  for (size_t j = 0; j < s.joints.size(); ++j) {
    int node = s.joints[j];
    if (node < 0 || size_t(node) >= nodeWorld.size()) {
      DeformFail(part + ".joints[" + std::to_string(j) + "]: node " + std::to_string(node) +
                 " does not exist");
    }
    glm::dmat4 ibm(1.0);
    if (!inverseBind.empty()) {
      for (int e = 0; e < 16; ++e) ibm[e / 4][e % 4] = inverseBind[16 * j + size_t(e)];  // column-major
    }
    joints.push_back(nodeWorld[size_t(node)] * ibm);
  }
  return joints;
}

void ApplyGltfSkin(const tinygltf::Model& model, const tinygltf::Primitive& p,
                   const std::vector<glm::dmat4>& joints, const glm::dmat4& meshWorld,
                   GltfVertices& v) {
  size_t n = v.positions.size();
  std::vector<double> ids[2], weights[2];
  for (int set = 0; set < 2; ++set) {
    ids[set] = PerVertex(model, p, "JOINTS_" + std::to_string(set), 4, n);
    weights[set] = PerVertex(model, p, "WEIGHTS_" + std::to_string(set), 4, n);
    if (ids[set].empty() != weights[set].empty()) {
      DeformFail("JOINTS_" + std::to_string(set) + " and WEIGHTS_" + std::to_string(set) +
                 " come in pairs");
    }
  }
  if (ids[0].empty()) DeformFail("a skinned mesh's primitive has no JOINTS_0 and WEIGHTS_0");
  for (size_t i = 0; i < n; ++i) {
    glm::dmat4 m(0.0);
    double sum = 0.0;
    for (int set = 0; set < 2 && !ids[set].empty(); ++set) {
      for (int k = 0; k < 4; ++k) {
        double w = weights[set][4 * i + size_t(k)], joint = ids[set][4 * i + size_t(k)];
        if (w == 0.0) continue;
        if (!(joint >= 0.0 && joint < double(joints.size()))) {
          DeformFail("JOINTS_" + std::to_string(set) + " names joint " + std::to_string(int64_t(joint)) +
                     " of a skin with " + std::to_string(joints.size()) + " joints");
        }
        m += w * joints[size_t(joint)];
        sum += w;
      }
    }
    m = sum > 0.0 ? m / sum : meshWorld;
    glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
    v.positions[i] = vec3(m * glm::dvec4(glm::dvec3(v.positions[i]), 1.0));
    if (!v.normals.empty()) {
      v.normals[i] = NormalizedOr(vec3(normalMatrix * glm::dvec3(v.normals[i])), v.normals[i]);
    }
    if (!v.tangents.empty()) {
      vec3 t = vec3(glm::dmat3(m) * glm::dvec3(vec3(v.tangents[i])));
      v.tangents[i] = vec4(NormalizedOr(t, vec3(v.tangents[i])), v.tangents[i].w);
    }
  }
}

}  // namespace pt
