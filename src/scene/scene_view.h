// What every stage body reads about the scene: a trivially copyable bundle of array pointers
// (host memory on the CPU backend, device memory on the GPU), captured by value in kernels.
#pragma once

#include "src/lights/light_bvh_types.h"
#include "src/scene/instance_types.h"
#include "src/scene/material_extension.h"
#include "src/scene/scene_types.h"

namespace pt {

// The one list of scene arrays. X(Type, name, host) declares SceneView::name, a `const Type*`
// the stages read, and names `host`, the std::vector<Type> of a Scene `s` that holds it.
// SceneView, HostSceneView, SceneBuffers and UploadScene all expand this list, so adding an
// array is one line here (and its vector in the Scene). An empty array is a null pointer.
#define PT_SCENE_ARRAYS(X)                                                                   \
  /* Geometry, in BVH order where it matters. */                                            \
  X(BvhNode, nodes, s.nodes)                  /* binary layout (empty when wide) */        \
  X(WideBvhNode, wideNodes, s.wideNodes)      /* wide layout (empty when binary) */        \
  X(PrimRef, prims, s.prims)                                                                \
  X(PackedTriangle, packedTriangles, s.packedTriangles) /* per prim, BVH order */           \
  X(Triangle, triangles, s.desc.triangles)                                                  \
  X(TriangleNormals, triangleNormals, s.desc.triangleNormals)                               \
  X(TriangleUvs, triangleUvs, s.desc.triangleUvs) /* null when no mesh has UVs */           \
  X(TriangleUvs, triangleUvs1, s.desc.triangleUvs1) /* TEXCOORD_1: null unless read */      \
  X(TriangleTangents, triangleTangents, s.desc.triangleTangents) /* null unless given */    \
  X(TriangleColors, triangleColors, s.desc.triangleColors) /* null unless COLOR_0 */        \
  X(Quad, quads, s.desc.quads)                                                              \
  X(Sphere, spheres, s.desc.spheres)                                                        \
  /* Instancing (empty in flat scenes): the top level over instances; src/scene/instances.h */ \
  X(Instance, instances, s.instances)                                                       \
  X(uint32_t, instanceOrder, s.instanceOrder) /* instance of each top-level leaf slot */   \
  X(BvhNode, tlasNodes, s.tlasNodes)          /* top level, binary layout */                \
  X(WideBvhNode, tlasWideNodes, s.tlasWideNodes) /* top level, wide layout */              \
  /* Appearance and light. */                                                               \
  X(Material, materials, s.desc.materials)                                                  \
  X(GltfMaterialExtension, materialExts, s.desc.materialExtensions) /* Material::ext */      \
  X(Texture, textures, s.desc.textures)                                                     \
  X(TextureRef, textureRefs, s.desc.textureRefs) /* what materials' texture slots index */  \
  X(uint32_t, texels, s.desc.texels) /* RGBA8 pyramids of every texture, back to back */    \
  X(Light, lights, s.lights)                                                                \
  X(float, lightPmf, s.lightPmf) /* probability of choosing each light */                   \
  X(float, lightCdf, s.lightCdf) /* lightCount + 1 entries, [0] = 0, last = 1 */            \
  X(uint32_t, distantLights, s.distantLights) /* directional lights escaped rays can hit */ \
  X(LightBvhNode, lightNodes, s.lightNodes)   /* the light BVH (src/lights/light_bvh.h) */  \
  X(uint64_t, lightTrails, s.lightTrails)     /* per finite light: its path in the tree */  \
  /* The environment map: texels (rows top to bottom), then its sampling distribution. */   \
  X(vec3, envTexels, s.desc.environment.texels)                                             \
  X(float, envRowCdf, s.envRowCdf) /* height + 1 entries over rows */                       \
  X(float, envColumnCdf, s.envColumnCdf) /* width + 1 entries per row */

// SceneView::triangleTest (--tri-test; TriangleTest's values): the watertight test (Woop et
// al.), Moller-Trumbore (a robustness study), or the watertight test with each hit's distance
// raised to its primitive's box entry (shapes.h: the closest hit never depends on the tree).
constexpr uint32_t kTriTestWatertight = 0, kTriTestMollerTrumbore = 1, kTriTestBoxClamped = 2;

struct SceneView {
#define PT_SCENE_VIEW_FIELD(Type, name, host) const Type* name = nullptr;
  PT_SCENE_ARRAYS(PT_SCENE_VIEW_FIELD)
#undef PT_SCENE_VIEW_FIELD

  uint32_t nodeCount = 0;  // of the layout in use
  uint32_t instanceCount = 0;  // 0: a flat scene (one BVH over prims, nothing instanced)
  uint32_t tlasNodeCount = 0;  // top-level nodes of the layout in use
  uint32_t primCount = 0;
  BvhLayout bvhLayout = BvhLayout::kBinary;
  uint32_t triangleTest = kTriTestWatertight;  // one of the kTriTest values above
  uint32_t materialCount = 0;
  uint32_t lightCount = 0;
  int32_t backgroundLight = -1;     // index of the background in lights, or -1 when black
  uint32_t distantLightCount = 0;   // directional lights with an angular radius

  vec3 background = vec3(0.0f);
  vec3 sceneCenter = vec3(0.0f);    // bounding sphere, for the background light's power
  float sceneRadius = 1.0f;

  EnvironmentView env;
  LightTreeView lightTree;  // the light sampler and the light BVH's grid
  Camera camera;
};

}  // namespace pt
