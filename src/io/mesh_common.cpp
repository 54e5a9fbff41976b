#include "src/io/mesh_common.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <utility>

#include "src/core/parallel_ranges.h"
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

// Three texture coordinates with non-finite ones (which would poison lookups) as zeros.
TriangleUvs FiniteUvs(const vec2* uvs) {
  vec2 uv[3];
  for (int i = 0; i < 3; ++i) {
    bool finite = std::isfinite(uvs[i].x) && std::isfinite(uvs[i].y);
    uv[i] = finite ? uvs[i] : vec2(0.0f);
  }
  return TriangleUvs{uv[0], uv[1], uv[2]};
}

// Makes room for `count` more triangles in an optional per-triangle array: backfilled with
// `fill` when the batch brings the data (AppendOptional's rule), else grown with `fill` once the
// array exists.
template <typename T>
void GrowOptional(std::vector<T>& all, size_t base, size_t count, bool has, T fill = T{}) {
  if (!has && all.empty()) return;
  all.resize(base, fill);
  all.resize(base + count, fill);
}

const TriangleColors kWhiteColors{vec4(1.0f), vec4(1.0f), vec4(1.0f)};

// Primitives of fewer triangles per thread stay on one thread.
constexpr size_t kMinBatchPerThread = 1 << 12;

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
  for (int i = 0; i < 3; ++i) w[i] = vec3(toWorld_ * glm::dvec4(glm::dvec3(p[i]), 1.0));
  if (IsDegenerateTriangle(w[0], w[1], w[2])) return false;
  out = Triangle{w[0], w[1], w[2]};
  return true;
}

void MeshSink::Convert(const VertexAttributes& a, WorldTriangle& out) const {
  if (a.normals) {
    vec3 n[3];
    bool valid = true;
    for (int i = 0; i < 3; ++i) {
      glm::dvec3 d = normalMatrix_ * glm::dvec3(a.normals[i]);
      double len = glm::length(d);
      valid = valid && len > 0.0 && std::isfinite(len);
      n[i] = valid ? vec3(d / len) : vec3(0.0f);
    }
    if (valid) out.normals = TriangleNormals{n[0], n[1], n[2]};
  }
  if (a.uvs) out.uvs = FiniteUvs(a.uvs);
  if (a.uvs1) out.uvs1 = FiniteUvs(a.uvs1);
  if (a.tangents) {
    // Tangents lie in the surface: they map as directions; a mirroring transform flips the
    // bitangent's handedness relative to the transformed normal.
    double handedness = glm::determinant(glm::dmat3(toWorld_)) < 0.0 ? -1.0 : 1.0;
    vec4* t[3] = {&out.tangents.t0, &out.tangents.t1, &out.tangents.t2};
    for (int i = 0; i < 3; ++i) {
      glm::dvec3 d = glm::dmat3(toWorld_) * glm::dvec3(vec3(a.tangents[i]));
      double len = glm::length(d);
      vec3 dir = len > 0.0 && std::isfinite(len) ? vec3(d / len) : vec3(0.0f);
      *t[i] = vec4(dir, float(handedness) * (a.tangents[i].w < 0.0f ? -1.0f : 1.0f));
    }
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

VertexAttributes MeshSink::Fetch(size_t t, const VertexPresence& has,
                                 const std::function<void(size_t, TriangleVertices&)>& fetch,
                                 TriangleVertices& v) const {
  fetch(t, v);
  if (mirrored_) {  // as Add: vertices 1 and 2 trade places with their attributes
    std::swap(v.p[1], v.p[2]);
    std::swap(v.normals[1], v.normals[2]);
    std::swap(v.uvs[1], v.uvs[2]);
    std::swap(v.uvs1[1], v.uvs1[2]);
    std::swap(v.tangents[1], v.tangents[2]);
    std::swap(v.colors[1], v.colors[2]);
  }
  return AttributesOf(v, has);
}

VertexAttributes AttributesOf(const TriangleVertices& v, const VertexPresence& has) {
  VertexAttributes a;
  if (has.normals) a.normals = v.normals;
  if (has.uvs) a.uvs = v.uvs;
  if (has.uvs1) a.uvs1 = v.uvs1;
  if (has.tangents) a.tangents = v.tangents;
  if (has.colors) a.colors = v.colors;
  return a;
}

namespace {

// Moves `count` elements of a per-triangle array from `from` down to `to` (to <= from).
template <typename T>
void MoveDown(std::vector<T>& all, size_t from, size_t to, size_t count) {
  if (all.size() < from + count || from == to) return;
  std::copy(all.begin() + ptrdiff_t(from), all.begin() + ptrdiff_t(from + count),
            all.begin() + ptrdiff_t(to));
}

}  // namespace

// The scene's arrays grow by `count` first and each range writes its kept triangles in place
// (no copy through a buffer of its own: for big scenes the fresh pages are most of the time);
// gaps left by skipped (degenerate) triangles are closed afterwards, in range order.
void MeshSink::AddBatch(size_t count, const VertexPresence& has, uint32_t material,
                        const std::function<void(size_t, TriangleVertices&)>& fetch) {
  size_t cores = std::max(1u, std::thread::hardware_concurrency());
  size_t ranges = std::clamp<size_t>(count / kMinBatchPerThread, 1, cores);
  if (ranges == 1) {  // one thread: Add in order
    TriangleVertices one;
    for (size_t t = 0; t < count; ++t) {
      VertexAttributes a = Fetch(t, has, fetch, one);
      AddInOrder(one.p, a, material);
    }
    return;
  }
  size_t base = scene_.triangles.size();
  GrowTriangles(base, count, has, material);
  std::vector<size_t> kept(ranges);
  auto first = [&](size_t r) { return base + count * r / ranges; };
  ForRangesOnThreads(ranges, int(ranges), 1, [&](size_t lo, size_t hi) {
    TriangleVertices v;
    for (size_t r = lo; r < hi; ++r) {
      size_t out = first(r);
      for (size_t t = count * r / ranges; t < count * (r + 1) / ranges; ++t) {
        VertexAttributes a = Fetch(t, has, fetch, v);
        WorldTriangle w;
        if (!ToWorld(v.p, w.positions)) continue;
        Convert(a, w);
        Store(w, has, out++);
      }
      kept[r] = out - first(r);
    }
  });
  size_t at = base + kept[0];
  for (size_t r = 1; r < ranges; ++r) {
    if (first(r) != at) {
      MoveDown(scene_.triangles, first(r), at, kept[r]);
      MoveDown(scene_.triangleNormals, first(r), at, kept[r]);
      if (has.uvs) MoveDown(scene_.triangleUvs, first(r), at, kept[r]);
      if (has.uvs1) MoveDown(scene_.triangleUvs1, first(r), at, kept[r]);
      if (has.tangents) MoveDown(scene_.triangleTangents, first(r), at, kept[r]);
      if (has.colors) MoveDown(scene_.triangleColors, first(r), at, kept[r]);
    }
    at += kept[r];
  }
  scene_.skippedDegenerateTriangles += int(base + count - at);
  ShrinkTriangles(at);
}

// Room for `count` more triangles in every per-triangle array the scene keeps (the optional
// ones by AppendOptional's rule), the material already in place.
void MeshSink::GrowTriangles(size_t base, size_t count, const VertexPresence& has,
                             uint32_t material) {
  scene_.triangles.resize(base + count);
  scene_.triangleNormals.resize(base + count);
  scene_.triangleMaterials.resize(base + count, HasOverride() ? Override() : material);
  GrowOptional(scene_.triangleUvs, base, count, has.uvs);
  GrowOptional(scene_.triangleUvs1, base, count, has.uvs1);
  GrowOptional(scene_.triangleTangents, base, count, has.tangents);
  GrowOptional(scene_.triangleColors, base, count, has.colors, kWhiteColors);
}

void MeshSink::Store(const WorldTriangle& w, const VertexPresence& has, size_t at) {
  scene_.triangles[at] = w.positions;
  scene_.triangleNormals[at] = w.normals;
  if (has.uvs) scene_.triangleUvs[at] = w.uvs;
  if (has.uvs1) scene_.triangleUvs1[at] = w.uvs1;
  if (has.tangents) scene_.triangleTangents[at] = w.tangents;
  if (has.colors) scene_.triangleColors[at] = w.colors;
}

// Every per-triangle array cut to `size` triangles (the optional ones only where they exist).
void MeshSink::ShrinkTriangles(size_t size) {
  scene_.triangles.resize(size);
  scene_.triangleNormals.resize(size);
  scene_.triangleMaterials.resize(size);
  if (!scene_.triangleUvs.empty()) scene_.triangleUvs.resize(size);
  if (!scene_.triangleUvs1.empty()) scene_.triangleUvs1.resize(size);
  if (!scene_.triangleTangents.empty()) scene_.triangleTangents.resize(size);
  if (!scene_.triangleColors.empty()) scene_.triangleColors.resize(size);
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
