#include "src/io/mesh_common.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <utility>

#include "src/core/prefault.h"
#include "src/materials/texture.h"
#include "src/materials/texture_pyramid.h"
#include "src/scene/instances.h"

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
  // |e1 x e2| > 1e-10 |e1| |e2|, squared (no square roots: a big scene loads this per triangle;
  // float coordinates keep every square far inside double's range).
  glm::dvec3 e1 = glm::dvec3(p1) - glm::dvec3(p0), e2 = glm::dvec3(p2) - glm::dvec3(p0);
  glm::dvec3 c = glm::cross(e1, e2);
  return !(glm::dot(c, c) > 1e-20 * glm::dot(e1, e1) * glm::dot(e2, e2));
}

void ReserveTriangles(SceneDesc& scene, size_t total) {
  ReserveOnThreads(scene.triangles, total);
  ReserveOnThreads(scene.triangleNormals, total);
  ReserveOnThreads(scene.triangleMaterials, total);
  if (!scene.triangleUvs.empty()) ReserveOnThreads(scene.triangleUvs, total);
  if (!scene.triangleUvs1.empty()) ReserveOnThreads(scene.triangleUvs1, total);
  if (!scene.triangleTangents.empty()) ReserveOnThreads(scene.triangleTangents, total);
  if (!scene.triangleColors.empty()) ReserveOnThreads(scene.triangleColors, total);
}

TriangleUvs FiniteUvs(const vec2* uvs) {
  vec2 uv[3];
  for (int i = 0; i < 3; ++i) {
    bool finite = std::isfinite(uvs[i].x) && std::isfinite(uvs[i].y);
    uv[i] = finite ? uvs[i] : vec2(0.0f);
  }
  return TriangleUvs{uv[0], uv[1], uv[2]};
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
  mirrored_ = glm::determinant(glm::dmat3(toWorld)) < 0.0;
}

void MeshSink::PlaceInstance(int key, const glm::dmat4& toWorld,
                             const std::function<void()>& emit) {
  auto it = meshes_.find(key);
  if (it == meshes_.end()) {
    glm::dmat4 placing = toWorld_;
    SetTransform(glm::dmat4(1.0));
    uint32_t first = uint32_t(scene_.triangles.size());
    emit();
    uint32_t count = uint32_t(scene_.triangles.size()) - first;
    SetTransform(placing);
    int64_t mesh = -1;
    if (count > 0) {
      mesh = int64_t(scene_.meshes.size());
      scene_.meshes.push_back(MeshDesc{label_ + " mesh " + std::to_string(key), first, count});
    }
    it = meshes_.emplace(key, mesh).first;
  }
  if (it->second < 0) return;
  std::string why;
  if (!ValidInstanceTransform(toWorld, &why)) {
    ++skippedSingular_;
    return;
  }
  InstanceDesc instance;
  instance.mesh = uint32_t(it->second);
  instance.toWorld = toWorld;
  scene_.instances.push_back(instance);
}

namespace {

// Appends value (or T{} / fill when null) to an optional per-triangle array: it stays empty
// until the first triangle with data, which backfills the triangles before it.
template <typename T>
void AppendOptional(std::vector<T>& all, size_t triangle, const T* value, T fill = T{}) {
  if (value) {
    all.resize(triangle, fill);
    all.push_back(*value);
  } else if (!all.empty()) {
    all.push_back(fill);
  }
}

// Vertices 1 and 2 of an optional per-vertex array swapped into `out` (null stays null).
template <typename T>
const T* Swapped12(const T* in, T out[3]) {
  if (!in) return nullptr;
  out[0] = in[0];
  out[1] = in[2];
  out[2] = in[1];
  return out;
}

}  // namespace

// Under a mirroring transform vertices 1 and 2 trade places (with their attributes), so the
// world winding, and with it the front, stays the file's.
bool MeshSink::Add(const vec3 p[3], const VertexAttributes& a, uint32_t material) {
  if (!mirrored_) return AddInOrder(p, a, material);
  vec3 q[3], n[3];
  vec2 uv0[3], uv1[3];
  vec4 t[3], c[3];
  VertexAttributes swapped;
  Swapped12(p, q);
  swapped.normals = Swapped12(a.normals, n);
  swapped.uvs = Swapped12(a.uvs, uv0);
  swapped.uvs1 = Swapped12(a.uvs1, uv1);
  swapped.tangents = Swapped12(a.tangents, t);
  swapped.colors = Swapped12(a.colors, c);
  return AddInOrder(q, swapped, material);
}

struct MeshSink::WorldTriangle {
  Triangle positions;
  TriangleNormals normals;  // zero vectors: shading falls back to the geometric normal
  TriangleUvs uvs, uvs1;
  TriangleTangents tangents;
  TriangleColors colors;
};

bool MeshSink::ToWorld(const vec3 p[3], Triangle& out) const {
  vec3 w[3];
  for (int i = 0; i < 3; ++i) w[i] = WorldPosition(p[i]);
  if (IsDegenerateTriangle(w[0], w[1], w[2])) return false;
  out = Triangle{w[0], w[1], w[2]};
  return true;
}

vec3 MeshSink::WorldPosition(vec3 p) const {
  return vec3(toWorld_ * glm::dvec4(glm::dvec3(p), 1.0));
}

vec3 MeshSink::WorldNormal(vec3 n, bool& valid) const {
  glm::dvec3 d = normalMatrix_ * glm::dvec3(n);
  double len = glm::length(d);
  valid = len > 0.0 && std::isfinite(len);
  return valid ? vec3(d / len) : vec3(0.0f);
}

// Tangents lie in the surface: they map as directions; a mirroring transform flips the
// bitangent's handedness relative to the transformed normal.
vec4 MeshSink::WorldTangent(vec4 t) const {
  double handedness = mirrored_ ? -1.0 : 1.0;
  glm::dvec3 d = glm::dmat3(toWorld_) * glm::dvec3(vec3(t));
  double len = glm::length(d);
  vec3 dir = len > 0.0 && std::isfinite(len) ? vec3(d / len) : vec3(0.0f);
  return vec4(dir, float(handedness) * (t.w < 0.0f ? -1.0f : 1.0f));
}

void MeshSink::Convert(const VertexAttributes& a, WorldTriangle& out) const {
  if (a.normals) {
    vec3 n[3];
    bool valid = true;
    for (int i = 0; i < 3; ++i) {
      bool v = false;
      n[i] = WorldNormal(a.normals[i], v);
      valid = valid && v;
    }
    if (valid) out.normals = TriangleNormals{n[0], n[1], n[2]};
  }
  if (a.uvs) out.uvs = FiniteUvs(a.uvs);
  if (a.uvs1) out.uvs1 = FiniteUvs(a.uvs1);
  if (a.tangents) {
    out.tangents = TriangleTangents{WorldTangent(a.tangents[0]), WorldTangent(a.tangents[1]),
                                    WorldTangent(a.tangents[2])};
  }
  if (a.colors) out.colors = TriangleColors{a.colors[0], a.colors[1], a.colors[2]};
}

bool MeshSink::AddInOrder(const vec3 p[3], const VertexAttributes& a, uint32_t material) {
  WorldTriangle w;
  if (!ToWorld(p, w.positions)) {
    scene_.skippedDegenerateTriangles++;
    return false;
  }
  Convert(a, w);
  size_t index = scene_.triangles.size();
  AppendOptional(scene_.triangleUvs, index, a.uvs ? &w.uvs : nullptr);
  AppendOptional(scene_.triangleUvs1, index, a.uvs1 ? &w.uvs1 : nullptr);
  AppendOptional(scene_.triangleTangents, index, a.tangents ? &w.tangents : nullptr);
  AppendOptional(scene_.triangleColors, index, a.colors ? &w.colors : nullptr, kWhiteColors);
  scene_.triangles.push_back(w.positions);
  scene_.triangleNormals.push_back(w.normals);
  scene_.triangleMaterials.push_back(HasOverride() ? Override() : material);
  return true;
}

uint32_t MeshSink::AddMaterial(const Material& material, const std::string& name) {
  scene_.materials.push_back(material);
  scene_.materialNames.push_back(name);
  return uint32_t(scene_.materials.size() - 1);
}

int32_t MeshSink::AddMaterialExtension(const GltfMaterialExtension& extension) {
  scene_.materialExtensions.push_back(extension);
  return int32_t(scene_.materialExtensions.size() - 1);
}

int32_t MeshSink::AddTexture(uint32_t width, uint32_t height, TextureWrap wrapS, TextureWrap wrapT,
                             bool srgb, const std::vector<uint32_t>& texels) {
  // Lookups index a level's texels with int32 (row * width + column) from a uint32 offset.
  constexpr uint64_t kMaxTexels = uint64_t(INT32_MAX);
  uint64_t count = uint64_t(width) * height;
  uint64_t total = count > 0 ? PyramidTexelCount(width, height, nullptr) : 0;
  if (width == 0 || height == 0 || count != texels.size() || count > kMaxTexels ||
      scene_.texels.size() + total > uint64_t(UINT32_MAX)) {
    throw std::runtime_error("texture of " + std::to_string(width) + " x " +
                             std::to_string(height) + " texels is empty or too large");
  }
  Texture t;
  t.width = width;
  t.height = height;
  t.offset = uint32_t(scene_.texels.size());
  t.wrapS = wrapS;
  t.wrapT = wrapT;
  t.srgb = srgb ? 1u : 0u;
  std::vector<uint32_t> pyramid = BuildTexturePyramid(width, height, texels, srgb, &t.levels);
  scene_.texels.insert(scene_.texels.end(), pyramid.begin(), pyramid.end());
  scene_.textures.push_back(t);
  return int32_t(scene_.textures.size() - 1);
}

int32_t MeshSink::AddTextureRef(const TextureRef& ref) {
  scene_.textureRefs.push_back(ref);
  return int32_t(scene_.textureRefs.size() - 1);
}

int32_t MeshSink::AddTextureView(int32_t texture, TextureWrap wrapS, TextureWrap wrapT) {
  Texture t = scene_.textures.at(size_t(texture));
  t.wrapS = wrapS;
  t.wrapT = wrapT;
  scene_.textures.push_back(t);
  return int32_t(scene_.textures.size() - 1);
}

}  // namespace pt
