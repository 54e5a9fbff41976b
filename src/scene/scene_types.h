// The closed sets of shapes, materials and lights, as plain structs that live in device
// arrays. Device code dispatches on a tag with one switch; there are no virtual functions.
#pragma once

#include "src/core/math.h"

namespace pt {

// ---- Shapes (world space; transforms are applied at load time) ----
enum class ShapeType : uint32_t { kTriangle = 0, kQuad = 1, kSphere = 2 };

struct Triangle {
  vec3 p0, p1, p2;  // geometric normal = cross(p1 - p0, p2 - p0): counter-clockwise is front
};

// Per-triangle vertex normals; all zero when the mesh has none (then shading uses the
// geometric normal).
struct TriangleNormals {
  vec3 n0, n1, n2;
};

// Per-triangle texture coordinates (glTF TEXCOORD_0); only present when a mesh has them.
struct TriangleUvs {
  vec2 uv0, uv1, uv2;
};

struct Quad {
  vec3 origin, u, v;  // origin + s*u + t*v, s,t in [0,1]; normal = normalize(cross(u, v))
};

struct Sphere {
  vec3 center;
  float radius;
};

// One primitive of the BVH: which shape array and where in it. Stored in BVH leaf order.
struct PrimRef {
  uint32_t tagIndex;  // ShapeType in the top 2 bits, index into that shape's array below
  uint32_t material;  // index into the materials array
  int32_t light;      // index into the lights array when this primitive emits, else -1

  PT_HDI ShapeType Type() const { return ShapeType(tagIndex >> 30); }
  PT_HDI uint32_t Index() const { return tagIndex & 0x3fffffffu; }
  PT_HDI static uint32_t Pack(ShapeType t, uint32_t index) { return (uint32_t(t) << 30) | index; }
};

// ---- Materials ----
enum class MaterialType : uint32_t {
  kDiffuse = 0,
  kEmissive = 1,
  kConductor = 2,
  kDielectric = 3,
  kPlastic = 4,  // parsed by the format; rendering it arrives with rough materials
  kCount = 5,
};

struct Material {
  MaterialType type = MaterialType::kDiffuse;
  uint32_t twoSided = 0;       // emissive only
  vec3 albedo = vec3(0.0f);    // diffuse, conductor (F0), plastic base
  vec3 radiance = vec3(0.0f);  // emissive
  vec3 absorption = vec3(0.0f);  // dielectric: Beer-Lambert coefficient per unit length
  float ior = 1.5f;            // dielectric, plastic
  float roughness = 0.0f;      // conductor, dielectric, plastic (GGX alpha = roughness^2)
  int32_t baseColorTexture = -1;  // index into the textures; multiplies albedo
};

// ---- Textures ----
enum class TextureWrap : uint32_t { kRepeat = 0, kClampToEdge = 1, kMirroredRepeat = 2 };

// An RGB image stored linear (sRGB decoded at load) in SceneView::texels from `offset`.
struct Texture {
  uint32_t width = 0, height = 0;
  uint32_t offset = 0;
  TextureWrap wrapS = TextureWrap::kRepeat, wrapT = TextureWrap::kRepeat;
};

// ---- Lights ----
enum class LightType : uint32_t { kArea = 0, kPoint = 1, kBackground = 2 };

struct Light {
  LightType type = LightType::kArea;
  uint32_t prim = 0;          // area: index into the BVH-ordered PrimRef array
  vec3 radiance = vec3(0.0f);  // area and background: emitted radiance
  vec3 position = vec3(0.0f);  // point
  vec3 intensity = vec3(0.0f);  // point: W/sr
  uint32_t twoSided = 0;      // area
  int32_t instance = -1;      // area: the placement of an instanced mesh's triangle, or -1
};

// ---- BVH ----
// 32 bytes. Interior: count == 0 and the children are nodes leftOrFirst and leftOrFirst + 1.
// Leaf: count > 0 primitives starting at PrimRef index leftOrFirst.
struct BvhNode {
  vec3 boundsMin;
  uint32_t leftOrFirst;
  vec3 boundsMax;
  uint32_t count;

  PT_HDI bool IsLeaf() const { return count > 0; }
};

// Which node layout traversal walks (--bvh): both index the same kind of primitive array.
enum class BvhLayout : uint32_t { kBinary = 0, kWide = 1 };

// 80 bytes, read as five 16-byte loads: an 8-wide node with its children's boxes quantised to
// 8 bits per plane on a grid of power-of-two steps (Ylitie, Karras, Laine 2017, "Efficient
// incoherent ray traversal on GPUs through compressed wide BVHs"). A child box is
// [origin + qlo * scale, origin + qhi * scale] per axis, scale = 2^(exponent - 127), always
// containing the exact box (rounded outwards). Slots are ordered for the ray's octant at
// build time (see bvh_wide.cpp); interior children are stored consecutively from childBase in
// slot order, and the primitives of the leaf children consecutively from primBase.
struct alignas(16) WideBvhNode {
  vec3 origin;
  uint8_t exponent[3];
  uint8_t innerMask;  // bit s: slot s holds an interior child
  uint32_t childBase;
  uint32_t primBase;
  // Per slot: 0 empty; interior 0b001'11sss (24 + slot s); leaf with n = 1..3 primitives at
  // primBase + k: (2^n - 1) << 5 | k, k < 24. Traversal turns a hit slot into mask bits
  // (meta >> 5) << (meta & 31): primitive bits 0-23, interior bits 24-31.
  uint8_t meta[8];
  uint8_t qlo[3][8];  // [axis][slot]
  uint8_t qhi[3][8];
};

// A primitive's triangle in BVH order, padded for three 16-byte loads: what traversal reads
// instead of PrimRef + Triangle (two dependent loads of 12 and 36 bytes). `tag` is the
// PrimRef's tagIndex (the shape type says whether p0..p2 hold a triangle).
struct alignas(16) PackedTriangle {
  vec3 p0;
  uint32_t tag;
  vec3 p1;
  uint32_t material;
  vec3 p2;
  uint32_t pad;
};

// ---- Camera, resolved to a basis ----
struct Camera {
  vec3 position;
  vec3 forward, right, up;  // orthonormal; up is the true up
  float tanHalfFovY;
  float aspect;             // width / height of the whole image
  float apertureRadius;
  float focusDistance;      // to the plane perpendicular to forward
};

}  // namespace pt
