// What the glTF and OBJ loaders share: transforming triangles into world space, skipping
// degenerate ones, and adding the file's materials to the scene.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

// Zero area (repeated or collinear vertices) or a non-finite coordinate: such a triangle has no
// normal, so the loaders skip it (and count it).
bool IsDegenerateTriangle(vec3 p0, vec3 p1, vec3 p2);

// A library's multi-line message as one line (newlines become "; ").
std::string OneLine(std::string text);

// Capacity for `total` triangles in every per-triangle array the scene keeps (the optional
// ones where they exist), so that loading the rest of a big scene grows nothing.
void ReserveTriangles(SceneDesc& scene, size_t total);

// Optional per-vertex data of one triangle: three values each, or null when the mesh lacks it.
struct VertexAttributes {
  const vec3* normals = nullptr;
  const vec2* uvs = nullptr;       // TEXCOORD_0
  const vec2* uvs1 = nullptr;      // TEXCOORD_1
  const vec4* tangents = nullptr;  // xyz and the bitangent sign w
  const vec4* colors = nullptr;    // linear RGBA
};

// Three texture coordinates with non-finite ones (which would poison lookups) as zeros.
TriangleUvs FiniteUvs(const vec2* uvs);
// What a triangle without COLOR_0 has once the scene keeps colours.
inline const TriangleColors kWhiteColors{vec4(1.0f), vec4(1.0f), vec4(1.0f)};

// Which optional per-vertex arrays a primitive brings.
struct VertexPresence {
  bool normals = false, uvs = false, uvs1 = false, tangents = false, colors = false;
};

// An indexed primitive's vertices (a glTF primitive's): positions, and each optional attribute
// either empty (absent) or one per position.
struct IndexedVertices {
  std::vector<vec3> positions, normals;
  std::vector<vec2> uvs, uvs1;      // TEXCOORD_0, TEXCOORD_1
  std::vector<vec4> tangents;       // xyz and the bitangent sign w
  std::vector<vec4> colors;         // linear RGBA
  VertexPresence Presence() const {
    return {!normals.empty(), !uvs.empty(), !uvs1.empty(), !tangents.empty(), !colors.empty()};
  }
};

// Receives one mesh file's triangles. Positions are transformed in double precision by the
// current transform (node transforms composed with the object's); normals by its inverse
// transpose.
class MeshSink {
 public:
  // materialOverride: a scene material index for every triangle, or -1 for the file's own.
  MeshSink(SceneDesc& scene, const glm::dmat4& objectToWorld, int64_t materialOverride,
           std::string label);

  const std::string& Label() const { return label_; }
  bool HasOverride() const { return materialOverride_ >= 0; }
  uint32_t Override() const { return uint32_t(materialOverride_); }
  const glm::dmat4& ObjectToWorld() const { return objectToWorld_; }
  // KHR_materials_variants: the variant a glTF file's materials are taken from (empty: none).
  void SetVariant(std::string name) { variant_ = std::move(name); }
  const std::string& Variant() const { return variant_; }

  // toWorld maps the mesh's coordinates to world space. A mirroring one (negative determinant)
  // swaps two vertices of every triangle, so the front stays the outside (glTF's rule).
  void SetTransform(const glm::dmat4& toWorld);

  // Instancing. A file that places one of its meshes several times (glTF nodes sharing a mesh)
  // stores it once: PlaceInstance(key, toWorld, emit) calls emit() the first time a key is
  // placed, to Add the mesh's triangles in its own space, and adds an instance of it with
  // toWorld (a singular toWorld - glTF's way to hide a node - places nothing, and is counted).
  // Keys are the file's own mesh numbers. While a mesh of the scene's mesh table is loaded,
  // instances cannot nest: DisallowInstances() makes the loader flatten reused meshes instead.
  bool InstancesAllowed() const { return instancesAllowed_; }
  void DisallowInstances() { instancesAllowed_ = false; }
  void PlaceInstance(int key, const glm::dmat4& toWorld, const std::function<void()>& emit);
  // Instances PlaceInstance skipped for a singular transform.
  int SkippedSingularInstances() const { return skippedSingular_; }
  // Keeps each optional per-triangle array of SceneDesc (UVs, second UVs, tangents, colours)
  // parallel to the triangles once any triangle has that data (earlier and later triangles
  // without it get zeros; colours white). Positions and tangents are transformed by the
  // current transform, normals by its inverse transpose. Returns false when skipped.
  bool Add(const vec3 p[3], const VertexAttributes& attributes, uint32_t material);
  bool Add(const vec3 p[3], const vec3* normals, uint32_t material, const vec2* uvs = nullptr) {
    VertexAttributes a;
    a.normals = normals;
    a.uvs = uvs;
    return Add(p, a, material);
  }

  // Triangles given as vertex indices into v (3 per triangle, each < v.positions.size()): the
  // same triangles, values and skipped ones as Add of each triangle in order, with each vertex
  // transformed once and a big primitive on every core (src/io/mesh_indexed.cpp).
  void AddIndexed(const IndexedVertices& v, const std::vector<uint32_t>& indices,
                  uint32_t material);

  uint32_t AddMaterial(const Material& material, const std::string& name);
  // A glTF material's extension entry (Material::ext takes the index returned).
  int32_t AddMaterialExtension(const GltfMaterialExtension& extension);
  // Appends a texture: level 0's packed RGBA8 texels (width * height, rows top to bottom, RGB
  // sRGB-encoded when srgb) and the mip levels built from them; returns its index. Throws
  // std::runtime_error when the scene's texel storage would overflow.
  int32_t AddTexture(uint32_t width, uint32_t height, TextureWrap wrapS, TextureWrap wrapT,
                     bool srgb, const std::vector<uint32_t>& texels);
  int32_t AddTextureRef(const TextureRef& ref);
  const Texture& TextureAt(int32_t texture) const { return scene_.textures.at(size_t(texture)); }
  // A new texture sharing the texels of an existing one, with other wrap modes.
  int32_t AddTextureView(int32_t texture, TextureWrap wrapS, TextureWrap wrapT);
  void Warn(const std::string& message) { scene_.warnings.push_back(label_ + ": " + message); }

 private:
  struct WorldTriangle;  // one triangle's data as the scene stores it
  bool AddInOrder(const vec3 p[3], const VertexAttributes& attributes, uint32_t material);
  // The world-space triangle of p: false (out untouched) when it is degenerate.
  bool ToWorld(const vec3 p[3], Triangle& out) const;
  // The rest of a kept triangle's data in world space.
  void Convert(const VertexAttributes& attributes, WorldTriangle& out) const;
  // One vertex's position in world space (double precision, rounded once to float).
  vec3 WorldPosition(vec3 p) const;
  // One vertex's normal in world space, unit length; zero and `valid` false when it has none.
  vec3 WorldNormal(vec3 n, bool& valid) const;
  // One vertex's tangent in world space (unit xyz, w the bitangent's sign in world space).
  vec4 WorldTangent(vec4 t) const;
  // AddIndexed's steps on the scene's per-triangle arrays.
  void GrowTriangles(size_t base, size_t count, const VertexPresence& has, uint32_t material);
  void ShrinkTriangles(size_t size);
  struct OptionalArrays {
    bool uvs, uvs1, tangents, colors;  // whether the scene keeps that array yet
  };
  OptionalArrays Optionals() const;
  void KeepAbsent(const OptionalArrays& before);

  SceneDesc& scene_;
  glm::dmat4 objectToWorld_;
  int64_t materialOverride_;
  std::string label_;
  glm::dmat4 toWorld_{1.0};
  glm::dmat3 normalMatrix_{1.0};
  bool mirrored_ = false;  // the transform mirrors: Add swaps vertices 1 and 2
  bool instancesAllowed_ = true;
  std::string variant_;
  std::map<int, int64_t> meshes_;  // PlaceInstance key -> SceneDesc::meshes index, -1: empty
  int skippedSingular_ = 0;
};

}  // namespace pt
