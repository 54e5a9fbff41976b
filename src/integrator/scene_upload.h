// Puts a Scene's arrays where a backend's stages can read them, and points a SceneView at
// them: one expansion of PT_SCENE_ARRAYS, so a new array needs no line here.
#pragma once

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

template <typename Backend, typename T>
const T* UploadSceneArray(SceneBuffers<Backend>& b, const std::vector<T>& host) {
  static_assert(alignof(T) <= alignof(SceneWord), "scene struct over-aligned");
  if (host.empty()) return nullptr;
  b.arrays.push_back(std::make_unique<typename SceneBuffers<Backend>::Words>());
  b.arrays.back()->UploadBytes(host.data(), host.size() * sizeof(T));
  return reinterpret_cast<const T*>(b.arrays.back()->Data());
}

// A backend whose stages run on the host (Backend::kHostMemory) reads the Scene's own
// vectors in place; any other gets a copy of each array in its memory.
template <typename Backend>
void UploadScene(const Scene& scene, SceneBuffers<Backend>& b) {
  b.view = HostSceneView(scene);
  b.hostBytes = SceneArrayBytes(scene);
  b.arrays.clear();
  if constexpr (!Backend::kHostMemory) {
    const Scene& s = scene;
#define PT_SCENE_ARRAY_UPLOAD(Type, name, host) b.view.name = UploadSceneArray(b, host);
    PT_SCENE_ARRAYS(PT_SCENE_ARRAY_UPLOAD)
#undef PT_SCENE_ARRAY_UPLOAD
  }
}

}  // namespace pt
