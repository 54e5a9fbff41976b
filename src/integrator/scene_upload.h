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

template <typename Backend>
struct SceneBuffers {
  using Words = typename Backend::template Buffer<SceneWord>;
  std::vector<std::unique_ptr<Words>> arrays;  // empty when the backend reads host memory
  std::vector<std::unique_ptr<Words>> topLevel;  // the top-level arrays, replaced on their own
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
                        "lightCdf"}) {
    if (std::strcmp(n, name) == 0) return true;
  }
  return false;
}

template <typename Words, typename T>
const T* UploadSceneArray(std::vector<std::unique_ptr<Words>>& store, const std::vector<T>& host) {
  static_assert(alignof(T) <= alignof(SceneWord), "scene struct over-aligned");
  if (host.empty()) return nullptr;
  store.push_back(std::make_unique<Words>());
  store.back()->UploadBytes(host.data(), host.size() * sizeof(T));
  return reinterpret_cast<const T*>(store.back()->Data());
}

// A backend whose stages run on the host (Backend::kHostMemory) reads the Scene's own
// vectors in place; any other gets a copy of each array in its memory.
template <typename Backend>
void UploadScene(const Scene& scene, SceneBuffers<Backend>& b) {
  b.view = HostSceneView(scene);
  b.hostBytes = SceneArrayBytes(scene);
  b.arrays.clear();
  b.topLevel.clear();
  if constexpr (!Backend::kHostMemory) {
    const Scene& s = scene;
#define PT_SCENE_ARRAY_UPLOAD(Type, name, host) \
  b.view.name = UploadSceneArray(IsTopLevelArray(#name) ? b.topLevel : b.arrays, host);
    PT_SCENE_ARRAYS(PT_SCENE_ARRAY_UPLOAD)
#undef PT_SCENE_ARRAY_UPLOAD
  }
}

// After RebuildTopLevel: the top-level arrays and the view's values that depend on instance
// placement (bounding sphere, top-level node count); everything else stays where it is.
template <typename Backend>
void UploadTopLevel(const Scene& scene, SceneBuffers<Backend>& b) {
  SceneView fresh = HostSceneView(scene);
  b.view.tlasNodeCount = fresh.tlasNodeCount;
  b.view.sceneCenter = fresh.sceneCenter;
  b.view.sceneRadius = fresh.sceneRadius;
  b.topLevel.clear();
  const Scene& s = scene;
  (void)s;
#define PT_SCENE_ARRAY_TOP_LEVEL(Type, name, host)                            \
  if (IsTopLevelArray(#name)) {                                               \
    if constexpr (Backend::kHostMemory) b.view.name = fresh.name;             \
    else b.view.name = UploadSceneArray(b.topLevel, host);                    \
  }
  PT_SCENE_ARRAYS(PT_SCENE_ARRAY_TOP_LEVEL)
#undef PT_SCENE_ARRAY_TOP_LEVEL
}

}  // namespace pt
