// The host-side scene: what the loader produces (settings, camera, materials, world-space
// shapes, point lights) and what BuildScene adds (BVH, BVH-ordered primitives, light table).
// A backend turns a Scene into a SceneView by copying each array to its memory.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "src/core/rng.h"
#include "src/geometry/aabb.h"
#include "src/media/media_desc.h"
#include "src/scene/scene_view.h"

namespace pt {

struct AdaptiveSettings {
  bool enabled = false;
  float tolerance = 0.05f;
  int minSpp = 16;
  int batch = 16;
};

// Limits the path state's flag word sets (src/integrator/path_state.h): a path's depth has 12
// bits, and the dielectric it is inside is kept as its material index + 1 in 17 bits.
constexpr int kMaxBounces = 4095;
constexpr size_t kMaxMaterials = (size_t(1) << 17) - 1;

struct RenderSettings {
  int width = 0, height = 0;
  int spp = 0;
  int maxDepth = 0;
  uint32_t seed = 0;
  int russianRouletteDepth = 3;
  AdaptiveSettings adaptive;
  SamplerKind sampler = SamplerKind::kIndependent;  // "sampler" (docs/sampling.md)
  // > 0: the image's intended width / height (a glTF scene's camera aspect ratio, or its
  // default 16:9); --width or --height given alone then sets the other side from it.
  float aspect = 0.0f;
};

struct CameraDesc {
  vec3 position = vec3(0.0f);
  vec3 lookAt = vec3(0.0f, 0.0f, -1.0f);
  vec3 up = vec3(0.0f, 1.0f, 0.0f);
  float fovY = 45.0f;
  float apertureRadius = 0.0f;
  float focusDistance = -1.0f;  // < 0: distance from position to look_at
  // Frame the scene's bounds when the scene is built (src/scene/auto_camera.h): position,
  // look_at and up are then computed from the bounds and the image's aspect ratio.
  bool autoFrame = false;
};

struct PointLightDesc {
  vec3 position;
  vec3 intensity;
};

// A spot light: a point light at `position` shining along unit `direction`, of `intensity`
// (W/sr) on its axis, full inside innerAngle and falling smoothly to 0 at outerAngle (radians,
// 0 <= inner < outer <= pi/2; the falloff of glTF KHR_lights_punctual, Light::SpotFalloff).
struct SpotLightDesc {
  vec3 position = vec3(0.0f);
  vec3 direction = vec3(0.0f, 0.0f, -1.0f);
  vec3 intensity = vec3(0.0f);
  float innerAngle = 0.0f;
  float outerAngle = 0.7853982f;  // pi/4, glTF's default
};

// A distant light: irradiance (W/m^2) on a plane facing it, from a cone of directions of
// half-angle angularRadius (radians) about `direction` (towards the light), uniform radiance
// irradiance / (pi sin^2 angularRadius) inside it; angularRadius 0 is a delta light. A sun of
// the environment's sky (partOfEnvironment) turns with environment.rotate and scales with
// environment.strength.
struct DirectionalLightDesc {
  vec3 direction = vec3(0.0f, 1.0f, 0.0f);
  vec3 irradiance = vec3(0.0f);
  float angularRadius = 0.0f;
  bool partOfEnvironment = false;
};

// The analytic sky (src/lights/sky.h): Preetham et al. 1999 for the sky dome, a ground of
// constant radiance below the horizon, and optionally the sun as a directional light.
struct SkyDesc {
  vec3 sunDirection = vec3(0.0f, 1.0f, 0.0f);  // unit, towards the sun, in the map's frame
  float turbidity = 3.0f;                      // [1.7, 10]: clear to hazy
  vec3 groundAlbedo = vec3(0.3f);
  bool sun = true;                             // add the sun disk as a directional light
  int width = 1024;                            // of the map the sky is baked into (2:1)
};

// The environment: what rays that leave the scene see. A constant `background` (SceneDesc),
// or an equirectangular map (read from a file, or an analytic sky baked at load) turned by
// `rotateDegrees` (as object transforms: Rz * Ry * Rx) and scaled by `strength`.
struct EnvironmentDesc {
  std::string file;   // the map's file as given; empty for a sky or no map
  std::string field;  // where it was named ("environment.file", "--env"), for messages
  bool isSky = false;
  SkyDesc sky;
  uint32_t width = 0, height = 0;  // 0: no map
  std::vector<vec3> texels;        // linear RGB, rows top to bottom
  float strength = 1.0f;
  vec3 rotateDegrees = vec3(0.0f);
  bool visibleToCamera = true;     // false: camera rays that escape see cameraColor
  vec3 cameraColor = vec3(0.0f);

  bool HasMap() const { return width > 0 && height > 0; }
};

// Everything the loader hands over. Shapes are already in world space.
// A mesh stored once for instances to place: a range of SceneDesc::triangles (with their
// normals, UVs and materials) in the mesh's own object space.
struct MeshDesc {
  std::string name;  // for messages: "file.glb" or "file.glb mesh 3"
  uint32_t firstTriangle = 0;
  uint32_t triangleCount = 0;
};

// One placement of a mesh.
struct InstanceDesc {
  uint32_t mesh = 0;           // index into SceneDesc::meshes
  glm::dmat4 toWorld{1.0};     // object -> world; affine and invertible
  int32_t material = -1;       // every triangle's material, or -1 for the mesh's own
};

// Everything the loader hands over. Shapes are in world space, except the triangles of
// `meshes`, which are in their mesh's object space and appear only where `instances` place them.
struct SceneDesc {
  std::string path;  // the scene file, for messages
  RenderSettings render;
  CameraDesc camera;
  vec3 background = vec3(0.0f);
  EnvironmentDesc environment;

  std::vector<Material> materials;
  std::vector<std::string> materialNames;  // same order as materials
  std::vector<GltfMaterialExtension> materialExtensions;  // Material::ext indexes these

  std::vector<Triangle> triangles;
  std::vector<TriangleNormals> triangleNormals;  // same length as triangles
  std::vector<TriangleUvs> triangleUvs;  // empty, or same length as triangles
  std::vector<TriangleUvs> triangleUvs1;  // TEXCOORD_1: empty, or same length as triangles
  std::vector<TriangleTangents> triangleTangents;  // empty, or same length as triangles
  std::vector<TriangleColors> triangleColors;  // empty, or same length as triangles
  std::vector<uint32_t> triangleMaterials;
  std::vector<Quad> quads;
  std::vector<uint32_t> quadMaterials;
  std::vector<Sphere> spheres;
  std::vector<uint32_t> sphereMaterials;
  std::vector<PointLightDesc> pointLights;
  std::vector<DirectionalLightDesc> directionalLights;
  std::vector<SpotLightDesc> spotLights;
  std::vector<MeshDesc> meshes;          // empty in a flat scene
  std::vector<InstanceDesc> instances;   // placements of meshes; at least one per mesh
  std::vector<Texture> textures;
  std::vector<TextureRef> textureRefs;  // Material texture slots index these
  std::vector<uint32_t> texels;  // RGBA8 pyramids of every texture, back to back
  MediaDesc media;  // participating media (src/media/): empty in a scene without them

  std::vector<std::string> warnings;  // printed by the app (glTF fallbacks and the like)
  int skippedDegenerateTriangles = 0;
};

enum class BvhBuilder : uint32_t {
  kSah = 0,   // binned SAH over centroids (Wald 2007): the default
  kSbvh = 1,  // binned SAH plus spatial splits (Stich, Friedrich, Dietrich 2009)
  kLbvh = 2,  // linear BVH from Morton codes (Karras 2012; src/geometry/lbvh.h): --bvh-build gpu
  kAuto = 3,  // kLbvh for meshes of kLbvhAutoPrims+ primitives with a device runner, else kSah
};

struct BvhBuildResult;
struct WideBvhResult;
// kLbvh and kAuto pick the linear BVH where the BVH build would dominate the time to the
// image and a GPU builds it (docs/bvh.md): from this many primitives.
constexpr size_t kLbvhAutoPrims = size_t(1) << 20;

struct BvhBuildOptions {
  int maxLeafSize = 4;  // binary layout (the wide layout's leaves hold at most 3)
  // The top level's leaves (instances): one by default, an instance's test being a whole
  // bottom-level walk, far dearer than the node test a bigger leaf saves. Tests vary it.
  int topLevelLeafSize = 1;
  int binCount = 16;
  BvhBuilder builder = BvhBuilder::kSah;
  BvhLayout layout = BvhLayout::kBinary;
  int threads = 0;  // build threads; 0 = all cores
  // kLbvh: builds on a device (the app's; false when it has none: the host's threads build),
  // the binary tree, or for the wide layout the wide one (collapsed there too).
  std::function<bool(const std::vector<Aabb>& bounds, BvhBuildResult* out)> deviceLbvh =
      nullptr;
  std::function<bool(const std::vector<Aabb>& bounds, WideBvhResult* out)> deviceWideLbvh =
      nullptr;
};

const char* BvhBuilderName(BvhBuilder b);
const char* BvhLayoutName(BvhLayout l);

// The scene ready to render: BVH built, primitives reordered, lights tabulated.
struct Scene {
  SceneDesc desc;
  Camera camera;

  BvhLayout bvhLayout = BvhLayout::kBinary;
  std::vector<BvhNode> nodes;          // binary layout (empty when wide)
  std::vector<WideBvhNode> wideNodes;  // wide layout (empty when binary)
  std::vector<PrimRef> prims;  // BVH leaf order (with spatial splits a shape may appear twice)
  std::vector<PackedTriangle> packedTriangles;  // same order as prims
  std::vector<Light> lights;
  std::vector<float> lightPmf, lightCdf;
  std::vector<uint32_t> distantLights;        // directional lights with a cone
  std::vector<float> envRowCdf, envColumnCdf;  // the map's sampling distribution
  EnvironmentView env;
  std::vector<double> lightPower;  // host only: each light's power, what lightPmf follows
  std::vector<LightBvhNode> lightNodes;  // the light BVH (src/lights/light_bvh_build.h)
  std::vector<uint64_t> lightTrails;     // per finite light: its path from the root, or 0
  LightTreeView lightTree;
  double lightBvhBuildMs = 0.0;
  int32_t backgroundLight = -1;
  vec3 sceneCenter = vec3(0.0f);
  float sceneRadius = 1.0f;
  double bvhBuildMs = 0.0;  // build, collapse to the wide layout included
  double bvhSahCost = 0.0;  // of the layout in use (BinarySahCost / WideBvhResult::sahCost)
  int bvhDepth = 0;

  // Instancing (all empty in a flat scene; src/scene/instances.h). With instances, nodes /
  // wideNodes and prims hold one bottom level after another: the world-space primitives' (if
  // any) first, then each mesh's.
  struct MeshBvh {
    uint32_t nodeOffset = 0, nodeCount = 0, primOffset = 0, primCount = 0;
    vec3 lo = vec3(0.0f), hi = vec3(0.0f);  // object-space bounds of the mesh
  };
  std::vector<MeshBvh> meshBvhs;      // per desc.meshes entry, then the world's (if any)
  std::vector<Instance> instances;    // per desc.instances entry, then the world's (if any)
  std::vector<uint32_t> instanceOrder;  // instance of each top-level leaf slot
  std::vector<BvhNode> tlasNodes;       // top level, binary layout
  std::vector<WideBvhNode> tlasWideNodes;  // top level, wide layout
  uint32_t worldPrimCount = 0;        // prims [0, worldPrimCount) are world-space primitives
  BvhBuildOptions bvhOptions;         // as built, for RebuildTopLevel
  double tlasBuildMs = 0.0;           // last top-level build

  bool HasInstances() const { return !instances.empty(); }
  // Triangles as placed in the world: each instance counts its mesh's triangles.
  uint64_t PlacedTriangleCount() const;

  uint32_t NodeCount() const {
    return uint32_t(bvhLayout == BvhLayout::kWide ? wideNodes.size() : nodes.size());
  }
  uint32_t TlasNodeCount() const {
    return uint32_t(bvhLayout == BvhLayout::kWide ? tlasWideNodes.size() : tlasNodes.size());
  }
  size_t NodeBytes() const {
    return nodes.size() * sizeof(BvhNode) + wideNodes.size() * sizeof(WideBvhNode) +
           tlasNodes.size() * sizeof(BvhNode) + tlasWideNodes.size() * sizeof(WideBvhNode);
  }

  size_t TriangleCount() const { return desc.triangles.size(); }
  size_t PrimitiveCount() const { return prims.size(); }
};

// Builds the BVH and light table. Throws std::runtime_error on a scene it cannot render.
Scene BuildScene(SceneDesc desc, const BvhBuildOptions& options = {});

// Resolves the camera basis (validated by the loader: up not parallel to forward), with the
// texture footprint of a render of `spp` samples per pixel (TextureFootprintScale); the
// three-argument form filters as for one sample.
Camera MakeCamera(const CameraDesc& desc, int width, int height, int spp);
Camera MakeCamera(const CameraDesc& desc, int width, int height);

// A view over host memory (the CPU backend and tests use it directly).
SceneView HostSceneView(const Scene& scene);

}  // namespace pt
