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

// Per-triangle texture coordinates (glTF TEXCOORD_0, and TEXCOORD_1 in a second array when a
// used texture reads it); only present when a mesh has them.
struct TriangleUvs {
  vec2 uv0, uv1, uv2;
};

// Per-triangle glTF TANGENT (xyz, w = bitangent sign), world space; only kept for meshes whose
// material has a normal texture and whose file gives tangents (else tangents come from UVs).
struct TriangleTangents {
  vec4 t0, t1, t2;
};

// Per-triangle glTF COLOR_0 (linear RGBA; RGB files get alpha 1); only present when a mesh has it.
struct TriangleColors {
  vec4 c0, c1, c2;
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
  // ShapeType in the top 2 bits, kHitTestBit, then the index into that shape's array.
  uint32_t tagIndex;
  uint32_t material;  // index into the materials array
  int32_t light;      // index into the lights array when this primitive emits, else -1

  // Set when the material may reject a geometric hit (alpha MASK/BLEND, single-sided culling):
  // only such primitives pay for the test in IntersectPrim (src/materials/alpha.h).
  static constexpr uint32_t kHitTestBit = 1u << 29;
  static constexpr uint32_t kIndexMask = kHitTestBit - 1u;

  PT_HDI ShapeType Type() const { return ShapeType(tagIndex >> 30); }
  PT_HDI uint32_t Index() const { return tagIndex & kIndexMask; }
  PT_HDI bool NeedsHitTest() const { return (tagIndex & kHitTestBit) != 0; }
  PT_HDI static uint32_t Pack(ShapeType t, uint32_t index, bool hitTest = false) {
    return (uint32_t(t) << 30) | (hitTest ? kHitTestBit : 0u) | index;
  }
};

// ---- Materials ----
enum class MaterialType : uint32_t {
  kDiffuse = 0,
  kEmissive = 1,
  kConductor = 2,
  kDielectric = 3,
  kPlastic = 4,
  kGltfPbr = 5,  // glTF metallic-roughness (+ transmission, volume, ior): src/materials/gltf_pbr.h
  kCount = 6,
};

// Bits of Material::flags (glTF materials).
enum MaterialFlag : uint32_t {
  kMaterialAlphaMask = 1u << 0,   // alphaMode MASK: hits with alpha < alphaCutoff are ignored
  kMaterialAlphaBlend = 1u << 1,  // alphaMode BLEND: a hit is kept with probability alpha
  kMaterialCullBack = 1u << 2,    // doubleSided false on an opaque material: back faces culled
  kMaterialThinWalled = 1u << 3,  // transmission without a volume: light passes the shell
  kMaterialUnlit = 1u << 4,       // KHR_materials_unlit: shows its base colour, scatters nothing
  // --energy-compensation on: rough metal lobes (glTF metal, conductor) gain the multiple
  // scattering single-scattering GGX loses (src/materials/energy_compensation.h).
  kMaterialEnergyCompensation = 1u << 5,
};

struct Material {
  MaterialType type = MaterialType::kDiffuse;
  uint32_t twoSided = 0;       // emissive, glTF (doubleSided): emits from both faces
  vec3 albedo = vec3(0.0f);    // diffuse, conductor (F0), plastic base, glTF base colour
  vec3 radiance = vec3(0.0f);  // emissive; glTF: emissiveFactor x emissive_strength
  vec3 absorption = vec3(0.0f);  // dielectric, glTF volume: Beer-Lambert coefficient per length
  float ior = 1.5f;            // dielectric, plastic, glTF
  float roughness = 0.0f;      // conductor, dielectric, plastic, glTF (GGX alpha = roughness^2)
  int32_t baseColorTexture = -1;  // index into the texture references; multiplies albedo
  // glTF only.
  uint32_t flags = 0;          // MaterialFlag bits
  float metallic = 0.0f;
  float transmission = 0.0f;   // KHR_materials_transmission factor
  float alpha = 1.0f;          // baseColorFactor's alpha
  float alphaCutoff = 0.5f;
  float normalScale = 1.0f;
  int32_t metallicRoughnessTexture = -1;  // texture references: B = metal, G = roughness
  int32_t normalTexture = -1;
  int32_t emissiveTexture = -1;
  int32_t transmissionTexture = -1;       // R multiplies the transmission factor
  int32_t ext = -1;  // glTF extensions (SceneView::materialExts), -1: none
};

// The type of m, or kType where a caller knows it at compile time (a shade kernel of one
// queue: src/integrator/shade_queues.h), so a switch on it folds to one case.
template <MaterialType kType>
PT_HDI MaterialType TypeOf(const Material& m) {
  return kType == MaterialType::kCount ? m.type : kType;
}

// ---- Textures ----
enum class TextureWrap : uint32_t { kRepeat = 0, kClampToEdge = 1, kMirroredRepeat = 2 };

// An RGBA8 image pyramid in SceneView::texels from `offset`: level 0 (width x height), then
// each level half the previous (rounded down, at least 1), box filtered at load, to 1 x 1.
// Texels are packed R | G << 8 | B << 16 | A << 24; RGB is sRGB-encoded when `srgb` is set
// (decoded per tap, before filtering), linear otherwise; alpha is always linear.
struct Texture {
  uint32_t width = 0, height = 0;
  uint32_t offset = 0;
  TextureWrap wrapS = TextureWrap::kRepeat, wrapT = TextureWrap::kRepeat;
  uint32_t levels = 1;
  uint32_t srgb = 0;
};

// One use of a texture by a material slot: which UV set and KHR_texture_transform's affine
// map, uv' = (row0 . (u, v, 1), row1 . (u, v, 1)).
struct TextureRef {
  int32_t texture = -1;
  uint32_t texCoord = 0;  // 0: TEXCOORD_0, 1: TEXCOORD_1
  vec3 row0 = vec3(1.0f, 0.0f, 0.0f);
  vec3 row1 = vec3(0.0f, 1.0f, 0.0f);
};

// ---- Lights ----
// kBackground is the constant environment; kEnvironmentMap the image one (its texels and
// sampling tables are SceneView arrays, its frame SceneView::env); kDirectional a distant
// light: a delta direction, or a cone of directions (a sun disk) sampled uniformly; kSpot a
// point light whose intensity falls off inside a cone (glTF KHR_lights_punctual's spot).
enum class LightType : uint32_t {
  kArea = 0,
  kPoint = 1,
  kBackground = 2,
  kDirectional = 3,
  kEnvironmentMap = 4,
  kSpot = 5,
};

struct Light {
  LightType type = LightType::kArea;
  uint32_t prim = 0;          // area: index into the BVH-ordered PrimRef array
  vec3 radiance = vec3(0.0f);  // area, background, directional disk: emitted radiance
  vec3 position = vec3(0.0f);  // point, spot
  vec3 intensity = vec3(0.0f);  // point, spot: W/sr (a spot's on its axis)
  uint32_t twoSided = 0;      // area
  // Directional: unit direction from the scene towards the light; the irradiance it gives a
  // plane facing it (W/m^2); the cone's half-angle as cos and as 1 - cos, the latter exact
  // for the sun's tiny cone where the difference would cancel. oneMinusCos == 0: a delta light.
  vec3 direction = vec3(0.0f, 1.0f, 0.0f);
  vec3 irradiance = vec3(0.0f);
  float cosAngle = 1.0f;
  float oneMinusCos = 0.0f;
  // Spot: `direction` is the unit axis the cone points along (away from the light); the
  // intensity towards unit w is intensity x SpotFalloff(dot(direction, w)), glTF's smooth
  // falloff: clamp(cos * spotScale + spotOffset, 0, 1)^2, 1 inside the inner cone and 0
  // outside the outer one.
  float spotScale = 0.0f;
  float spotOffset = 1.0f;

  int32_t instance = -1;      // area: the placement of an instanced mesh's triangle, or -1

  PT_HDI bool IsDeltaDirection() const { return oneMinusCos <= 0.0f; }
  PT_HDI float SpotFalloff(float cosAxis) const {
    float t = cosAxis * spotScale + spotOffset;
    t = t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f;
    return t * t;
  }
};

// Where an equirectangular environment map sits in the world and how it is sampled. Texel
// (i, j) (column i of width, row j of height, row 0 at the top) covers, in the map's frame,
// u = (i, i+1) / width and v = (j, j+1) / height with direction
//   theta = pi v (from +Y), phi = 2 pi (u - 1/2) (from -Z towards +X):
//   d = (sin theta sin phi, cos theta, -sin theta cos phi),
// so the image's centre column faces -Z, its top row +Y, and u grows towards +X.
// Camera rays that escape see cameraColor instead of the environment when hiddenFromCamera.
struct EnvironmentView {
  uint32_t width = 0, height = 0;  // 0: no map
  uint32_t uniformSampling = 0;    // 1: sample the sphere uniformly (--env-sampling uniform)
  int32_t light = -1;              // the map's index in the lights, -1 when it emits nothing
  float strength = 1.0f;           // radiance = strength x texel
  uint32_t hiddenFromCamera = 0;
  vec3 cameraColor = vec3(0.0f);
  mat3 toLocal = mat3(1.0f);       // world direction -> the map's frame (the inverse rotate)
  mat3 toWorld = mat3(1.0f);
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
  float pixelSpread;        // 2 tanHalfFovY / height: a pixel's angular width at the centre
  float textureFootprint;   // fraction of a pixel textures filter over (TextureFootprintScale)
  float apertureRadius;
  float focusDistance;      // to the plane perpendicular to forward
};

}  // namespace pt
