// The host-side scene: what the loader produces (settings, camera, materials, world-space
// shapes, point lights) and what BuildScene adds (BVH, BVH-ordered primitives, light table).
// A backend turns a Scene into a SceneView by copying each array to its memory.
#pragma once

#include <string>
#include <vector>

#include "src/scene/scene_view.h"

namespace pt {

struct AdaptiveSettings {
  bool enabled = false;
  float tolerance = 0.05f;
  int minSpp = 16;
  int batch = 16;
};

struct RenderSettings {
  int width = 0, height = 0;
  int spp = 0;
  int maxDepth = 0;
  uint32_t seed = 0;
  int russianRouletteDepth = 3;
  AdaptiveSettings adaptive;
};

struct CameraDesc {
  vec3 position = vec3(0.0f);
  vec3 lookAt = vec3(0.0f, 0.0f, -1.0f);
  vec3 up = vec3(0.0f, 1.0f, 0.0f);
  float fovY = 45.0f;
  float apertureRadius = 0.0f;
  float focusDistance = -1.0f;  // < 0: distance from position to look_at
};

struct PointLightDesc {
  vec3 position;
  vec3 intensity;
};

// Everything the loader hands over. Shapes are already in world space.
struct SceneDesc {
  std::string path;  // the scene file, for messages
  RenderSettings render;
  CameraDesc camera;
  vec3 background = vec3(0.0f);

  std::vector<Material> materials;
  std::vector<std::string> materialNames;  // same order as materials

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
  std::vector<Texture> textures;
  std::vector<TextureRef> textureRefs;  // Material texture slots index these
  std::vector<uint32_t> texels;  // RGBA8 pyramids of every texture, back to back

  std::vector<std::string> warnings;  // printed by the app (glTF fallbacks and the like)
  int skippedDegenerateTriangles = 0;
};

struct BvhBuildOptions {
  int maxLeafSize = 4;
  int binCount = 16;
};

// The scene ready to render: BVH built, primitives reordered, lights tabulated.
struct Scene {
  SceneDesc desc;
  Camera camera;

  std::vector<BvhNode> nodes;
  std::vector<PrimRef> prims;  // BVH leaf order
  std::vector<Light> lights;
  std::vector<float> lightPmf, lightCdf;
  int32_t backgroundLight = -1;
  vec3 sceneCenter = vec3(0.0f);
  float sceneRadius = 1.0f;
  double bvhBuildMs = 0.0;

  size_t TriangleCount() const { return desc.triangles.size(); }
  size_t PrimitiveCount() const { return prims.size(); }
};

// Builds the BVH and light table. Throws std::runtime_error on a scene it cannot render.
Scene BuildScene(SceneDesc desc, const BvhBuildOptions& options = {});

// Resolves the camera basis (validated by the loader: up not parallel to forward).
Camera MakeCamera(const CameraDesc& desc, int width, int height);

// A view over host memory (the CPU backend and tests use it directly).
SceneView HostSceneView(const Scene& scene);

}  // namespace pt
