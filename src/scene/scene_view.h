// What every stage body reads about the scene: a trivially copyable bundle of array pointers
// (host memory on the CPU backend, device memory on the GPU), captured by value in kernels.
#pragma once

#include "src/scene/scene_types.h"

namespace pt {

struct SceneView {
  // Geometry, in BVH order where it matters.
  const BvhNode* nodes = nullptr;
  const PrimRef* prims = nullptr;
  const Triangle* triangles = nullptr;
  const TriangleNormals* triangleNormals = nullptr;
  const Quad* quads = nullptr;
  const Sphere* spheres = nullptr;
  const TriangleUvs* triangleUvs = nullptr;  // null when no mesh has texture coordinates
  uint32_t nodeCount = 0;
  uint32_t primCount = 0;
  uint32_t triangleTest = 0;  // 0: watertight (Woop et al.); 1: Moller-Trumbore (a study)

  // Appearance and light.
  const Material* materials = nullptr;
  uint32_t materialCount = 0;
  const Texture* textures = nullptr;
  const vec3* texels = nullptr;
  const Light* lights = nullptr;
  const float* lightPmf = nullptr;  // probability of choosing each light
  const float* lightCdf = nullptr;  // lightCount + 1 entries, lightCdf[0] = 0, last = 1
  uint32_t lightCount = 0;
  int32_t backgroundLight = -1;     // index of the background in lights, or -1 when black

  vec3 background = vec3(0.0f);
  vec3 sceneCenter = vec3(0.0f);    // bounding sphere, for the background light's power
  float sceneRadius = 1.0f;

  Camera camera;
};

}  // namespace pt
