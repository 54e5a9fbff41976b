// What every stage body reads about the scene: a trivially copyable bundle of array pointers
// (host memory on the CPU backend, device memory on the GPU), captured by value in kernels.
#pragma once

#include "src/scene/scene_types.h"

namespace pt {

// The one list of scene arrays. X(Type, name, host) declares SceneView::name, a `const Type*`
// the stages read, and names `host`, the std::vector<Type> of a Scene `s` that holds it.
// SceneView, HostSceneView, SceneBuffers and UploadScene all expand this list, so adding an
// array is one line here (and its vector in the Scene). An empty array is a null pointer.
#define PT_SCENE_ARRAYS(X)                                                                 \
  /* Geometry, in BVH order where it matters. */                                           \
  X(BvhNode, nodes, s.nodes)                                                               \
  X(PrimRef, prims, s.prims)                                                               \
  X(Triangle, triangles, s.desc.triangles)                                                 \
  X(TriangleNormals, triangleNormals, s.desc.triangleNormals)                              \
  X(TriangleUvs, triangleUvs, s.desc.triangleUvs) /* null when no mesh has UVs */          \
  X(TriangleUvs, triangleUvs1, s.desc.triangleUvs1) /* TEXCOORD_1: null unless read */     \
  X(TriangleTangents, triangleTangents, s.desc.triangleTangents) /* null unless given */   \
  X(TriangleColors, triangleColors, s.desc.triangleColors) /* null unless COLOR_0 */       \
  X(Quad, quads, s.desc.quads)                                                             \
  X(Sphere, spheres, s.desc.spheres)                                                       \
  /* Appearance and light. */                                                              \
  X(Material, materials, s.desc.materials)                                                 \
  X(Texture, textures, s.desc.textures)                                                    \
  X(TextureRef, textureRefs, s.desc.textureRefs) /* what materials' texture slots index */ \
  X(uint32_t, texels, s.desc.texels) /* RGBA8 pyramids of every texture, back to back */   \
  X(Light, lights, s.lights)                                                               \
  X(float, lightPmf, s.lightPmf) /* probability of choosing each light */                  \
  X(float, lightCdf, s.lightCdf) /* lightCount + 1 entries, [0] = 0, last = 1 */

struct SceneView {
#define PT_SCENE_VIEW_FIELD(Type, name, host) const Type* name = nullptr;
  PT_SCENE_ARRAYS(PT_SCENE_VIEW_FIELD)
#undef PT_SCENE_VIEW_FIELD

  uint32_t nodeCount = 0;
  uint32_t primCount = 0;
  uint32_t triangleTest = 0;  // 0: watertight (Woop et al.); 1: Moller-Trumbore (a study)
  uint32_t materialCount = 0;
  uint32_t lightCount = 0;
  int32_t backgroundLight = -1;     // index of the background in lights, or -1 when black

  vec3 background = vec3(0.0f);
  vec3 sceneCenter = vec3(0.0f);    // bounding sphere, for the background light's power
  float sceneRadius = 1.0f;

  Camera camera;
};

}  // namespace pt
