// From loaded shapes to a renderable scene: BVH over every primitive, primitives in leaf
// order, the light table, and the camera basis.
#include <chrono>
#include <stdexcept>

#include "src/geometry/aabb.h"
#include "src/geometry/bvh.h"
#include "src/geometry/shapes.h"
#include "src/lights/light_table.h"
#include "src/scene/scene.h"

namespace pt {
namespace {

// Whether hits on a material's primitives need its verdict (src/materials/alpha.h).
bool NeedsHitTest(const Material& m) {
  return (m.flags & (kMaterialAlphaMask | kMaterialAlphaBlend | kMaterialCullBack)) != 0;
}

// Every shape as an unordered PrimRef with its bounds.
void CollectPrimitives(const SceneDesc& d, std::vector<PrimRef>& prims, std::vector<Aabb>& bounds) {
  auto add = [&](ShapeType type, uint32_t index, uint32_t material, const Aabb& box) {
    bool test = material < d.materials.size() && NeedsHitTest(d.materials[material]);
    prims.push_back(PrimRef{PrimRef::Pack(type, index, test), material, -1});
    bounds.push_back(box);
  };
  for (uint32_t i = 0; i < d.triangles.size(); ++i)
    add(ShapeType::kTriangle, i, d.triangleMaterials[i], TriangleBounds(d.triangles[i]));
  for (uint32_t i = 0; i < d.quads.size(); ++i)
    add(ShapeType::kQuad, i, d.quadMaterials[i], QuadBounds(d.quads[i]));
  for (uint32_t i = 0; i < d.spheres.size(); ++i)
    add(ShapeType::kSphere, i, d.sphereMaterials[i], SphereBounds(d.spheres[i]));
}

}  // namespace

Camera MakeCamera(const CameraDesc& desc, int width, int height) {
  Camera c;
  c.position = desc.position;
  c.forward = glm::normalize(desc.lookAt - desc.position);
  c.right = glm::normalize(glm::cross(c.forward, desc.up));
  c.up = glm::cross(c.right, c.forward);
  c.tanHalfFovY = std::tan(glm::radians(desc.fovY) * 0.5f);
  c.aspect = float(width) / float(height);
  c.pixelSpread = 2.0f * c.tanHalfFovY / float(height);
  c.apertureRadius = desc.apertureRadius;
  c.focusDistance = desc.focusDistance > 0.0f ? desc.focusDistance
                                              : glm::length(desc.lookAt - desc.position);
  return c;
}

Scene BuildScene(SceneDesc desc, const BvhBuildOptions& options) {
  Scene scene;
  scene.desc = std::move(desc);
  const SceneDesc& d = scene.desc;
  if (d.triangleNormals.size() != d.triangles.size())
    throw std::runtime_error("internal: triangle normals do not match triangles");
  scene.camera = MakeCamera(d.camera, d.render.width, d.render.height);

  std::vector<PrimRef> unordered;
  std::vector<Aabb> bounds;
  CollectPrimitives(d, unordered, bounds);

  auto t0 = std::chrono::steady_clock::now();
  BvhBuildResult bvh = BuildBvh(bounds, options);
  scene.bvhBuildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  scene.nodes = std::move(bvh.nodes);
  scene.prims.reserve(unordered.size());
  for (uint32_t i : bvh.primOrder) scene.prims.push_back(unordered[i]);

  Aabb world;
  for (const Aabb& b : bounds) world = Union(world, b);
  if (!bounds.empty()) {
    scene.sceneCenter = 0.5f * (world.lo + world.hi);
    scene.sceneRadius = std::max(1e-6f, 0.5f * glm::length(world.hi - world.lo));
  }
  BuildLightTable(scene);
  return scene;
}

SceneView HostSceneView(const Scene& scene) {
  const Scene& s = scene;
  const SceneDesc& d = scene.desc;
  SceneView v;
#define PT_SCENE_ARRAY_HOST(Type, name, host) v.name = (host).empty() ? nullptr : (host).data();
  PT_SCENE_ARRAYS(PT_SCENE_ARRAY_HOST)
#undef PT_SCENE_ARRAY_HOST
  v.nodeCount = uint32_t(scene.nodes.size());
  v.primCount = uint32_t(scene.prims.size());
  v.materialCount = uint32_t(d.materials.size());
  v.lightCount = uint32_t(scene.lights.size());
  v.backgroundLight = scene.backgroundLight;
  v.background = d.background;
  v.sceneCenter = scene.sceneCenter;
  v.sceneRadius = scene.sceneRadius;
  v.camera = scene.camera;
  return v;
}

}  // namespace pt
