#include "src/io/mesh_common.h"

#include <cmath>

namespace pt {

std::string OneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::string out;
  for (char c : text) out += (c == '\n') ? std::string("; ") : std::string(1, c);
  return out;
}

bool IsDegenerateTriangle(vec3 p0, vec3 p1, vec3 p2) {
  if (!IsFinite(p0) || !IsFinite(p1) || !IsFinite(p2)) return true;
  // The renderer's normal is this float cross product: it must be non-zero and finite.
  vec3 nf = glm::cross(p1 - p0, p2 - p0);
  float lengthSquared = glm::dot(nf, nf);
  if (!(lengthSquared > 0.0f) || !std::isfinite(lengthSquared)) return true;
  // Exactly collinear vertices can leave float rounding noise; in double the edges are exact
  // and the cross product of collinear ones is ~1e-16 relative, far below this bound.
  glm::dvec3 e1 = glm::dvec3(p1) - glm::dvec3(p0), e2 = glm::dvec3(p2) - glm::dvec3(p0);
  double area2 = glm::length(glm::cross(e1, e2));
  return !(area2 > 1e-10 * glm::length(e1) * glm::length(e2));
}

MeshSink::MeshSink(SceneDesc& scene, const glm::dmat4& objectToWorld, int64_t materialOverride,
                   std::string label)
    : scene_(scene),
      objectToWorld_(objectToWorld),
      materialOverride_(materialOverride),
      label_(std::move(label)) {
  SetTransform(objectToWorld);
}

void MeshSink::SetTransform(const glm::dmat4& toWorld) {
  toWorld_ = toWorld;
  normalMatrix_ = glm::transpose(glm::inverse(glm::dmat3(toWorld)));
}

bool MeshSink::Add(const vec3 p[3], const vec3* normals, uint32_t material) {
  vec3 w[3];
  for (int i = 0; i < 3; ++i) w[i] = vec3(toWorld_ * glm::dvec4(glm::dvec3(p[i]), 1.0));
  if (IsDegenerateTriangle(w[0], w[1], w[2])) {
    scene_.skippedDegenerateTriangles++;
    return false;
  }
  TriangleNormals tn;  // zero vectors: shading falls back to the geometric normal
  if (normals) {
    vec3 n[3];
    bool valid = true;
    for (int i = 0; i < 3; ++i) {
      glm::dvec3 d = normalMatrix_ * glm::dvec3(normals[i]);
      double len = glm::length(d);
      valid = valid && len > 0.0 && std::isfinite(len);
      n[i] = valid ? vec3(d / len) : vec3(0.0f);
    }
    if (valid) tn = TriangleNormals{n[0], n[1], n[2]};
  }
  scene_.triangles.push_back(Triangle{w[0], w[1], w[2]});
  scene_.triangleNormals.push_back(tn);
  scene_.triangleMaterials.push_back(HasOverride() ? Override() : material);
  return true;
}

uint32_t MeshSink::AddMaterial(const Material& material, const std::string& name) {
  scene_.materials.push_back(material);
  scene_.materialNames.push_back(name);
  return uint32_t(scene_.materials.size() - 1);
}

}  // namespace pt
