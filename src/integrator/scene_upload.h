// Puts a Scene's arrays where a backend's stages can read them, and points a SceneView at
// them: one expansion of PT_SCENE_ARRAYS, so a new array needs no line here.
#pragma once

#include <cstring>
#include <memory>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

// Storage unit of an uploaded array: 16-byte aligned, enough for every scene struct.
struct alignas(16) SceneWord {
  uint32_t w[4];
};

// How many arrays PT_SCENE_ARRAYS lists.
inline constexpr size_t kSceneArrayCount = 0
#define PT_SCENE_ARRAY_COUNT(Type, name, host) +1
    PT_SCENE_ARRAYS(PT_SCENE_ARRAY_COUNT)
#undef PT_SCENE_ARRAY_COUNT
    ;

template <typename Backend>
struct SceneBuffers {
  using Words = typename Backend::template Buffer<SceneWord>;
  // One slot per array of PT_SCENE_ARRAYS, in its order, so that a few arrays can be replaced
  // alone; empty when the backend reads host memory.
  std::vector<std::unique_ptr<Words>> arrays;
  size_t hostBytes = 0;                        // the arrays' size wherever they live
  SceneView view;

  size_t Bytes() const { return hostBytes; }
};

// The bytes of every array in the list.
inline size_t SceneArrayBytes(const Scene& s) {
  size_t bytes = 0;
#define PT_SCENE_ARRAY_BYTES(Type, name, host) bytes += (host).size() * sizeof(Type);
  PT_SCENE_ARRAYS(PT_SCENE_ARRAY_BYTES)
#undef PT_SCENE_ARRAY_BYTES
  return bytes;
}

// The arrays that RebuildTopLevel rewrites when instances move (src/scene/instances.h).
inline bool IsTopLevelArray(const char* name) {
  for (const char* n : {"instances", "instanceOrder", "tlasNodes", "tlasWideNodes", "lightPmf",
                        "lightCdf", "lightNodes", "lightTrails"}) {
    if (std::strcmp(n, name) == 0) return true;
  }
  return false;
}

template <typename Backend, typename T>
const T* UploadSceneArray(SceneBuffers<Backend>& b, size_t slot, const std::vector<T>& host) {
  static_assert(alignof(T) <= alignof(SceneWord), "scene struct over-aligned");
  if (host.empty()) {
    b.arrays[slot].reset();
    return nullptr;
  }
  if (!b.arrays[slot]) b.arrays[slot] = std::make_unique<typename SceneBuffers<Backend>::Words>();
  b.arrays[slot]->UploadBytes(host.data(), host.size() * sizeof(T));
  return reinterpret_cast<const T*>(b.arrays[slot]->Data());
}

// Uploads the arrays whose names (as PT_SCENE_ARRAYS spells them) `which` accepts and takes
// the view's counts and constants from the scene again; the other arrays stay where they are,
// and so do the view's camera, triangle test and environment sampling (session state). A backend whose stages run
// on the host (Backend::kHostMemory) reads the Scene's own vectors in place.
template <typename Backend, typename Which>
void UploadSceneArrays(const Scene& scene, SceneBuffers<Backend>& b, Which which) {
  SceneView fresh = HostSceneView(scene);
  SceneView old = b.view;
  b.view = fresh;
  b.view.camera = old.camera;
  b.view.triangleTest = old.triangleTest;
  b.view.env.uniformSampling = old.env.uniformSampling;
  b.view.lightTree.sampler = old.lightTree.sampler;
  b.hostBytes = SceneArrayBytes(scene);
  b.arrays.resize(kSceneArrayCount);
  const Scene& s = scene;
  size_t slot = 0;
  (void)s;
#define PT_SCENE_ARRAY_UPLOAD(Type, name, host)                                          \
  if (!which(#name)) b.view.name = old.name;                                             \
  else if constexpr (!Backend::kHostMemory) b.view.name = UploadSceneArray(b, slot, host); \
  ++slot;
  PT_SCENE_ARRAYS(PT_SCENE_ARRAY_UPLOAD)
#undef PT_SCENE_ARRAY_UPLOAD
}

// Every array, and the whole view (the scene's own camera).
template <typename Backend>
void UploadScene(const Scene& scene, SceneBuffers<Backend>& b) {
  UploadSceneArrays(scene, b, [](const char*) { return true; });
  b.view.camera = scene.camera;
  b.view.triangleTest = 0;
}

// The arrays a material edit touches: the materials, the primitives' light indices and the
// light table (an emitter's radiance sets its power; a material may start or stop emitting).
inline bool IsAppearanceArray(const char* name) {
  for (const char* n :
       {"materials", "prims", "lights", "lightPmf", "lightCdf", "lightNodes", "lightTrails"}) {
    if (std::strcmp(n, name) == 0) return true;
  }
  return false;
}

// After RebuildTopLevel: the top-level arrays and the view's values that depend on instance
// placement (bounding sphere, top-level node count); everything else stays where it is.
template <typename Backend>
void UploadTopLevel(const Scene& scene, SceneBuffers<Backend>& b) {
  UploadSceneArrays(scene, b, IsTopLevelArray);
}

}  // namespace pt
