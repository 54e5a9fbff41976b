// Shade queues: the classes of hit that `--sort queues` shades with kernels of their own, as
// pbrt-v4's wavefront integrator keeps one work queue per material type. A queue is a
// material type with or without textures (texture lookups, normal maps and vertex colours
// are most of a textured material's cost), plus one queue for paths that escaped the scene.
// Each queue's kernel is compiled for its queue only: the material type is a compile-time
// constant there, so every switch on it folds to one case.
#pragma once

#include <cstdint>

#include "src/scene/effects.h"
#include "src/scene/scene_types.h"

namespace pt {

constexpr uint32_t kMaterialTypeCount = uint32_t(MaterialType::kCount);
// Queue 2 t + 0: material type t without textures; 2 t + 1: with; then escaped paths.
constexpr uint32_t kEscapedQueue = 2 * kMaterialTypeCount;
constexpr uint32_t kShadeQueueCount = kEscapedQueue + 1;
// The template argument of the one shade kernel that handles every queue (no per-queue code).
constexpr uint32_t kAnyQueue = 0xffffffffu;

PT_HDI bool HasTextures(const Material& m) {
  return m.baseColorTexture >= 0 || m.metallicRoughnessTexture >= 0 || m.normalTexture >= 0 ||
         m.emissiveTexture >= 0 || m.transmissionTexture >= 0;
}

PT_HDI uint32_t ShadeQueueOf(const Material& m) {
  return 2 * uint32_t(m.type) + (HasTextures(m) ? 1u : 0u);
}

constexpr MaterialType QueueMaterialType(uint32_t q) { return MaterialType(q / 2); }
constexpr bool QueueTextured(uint32_t q) { return q < kEscapedQueue && (q & 1u) != 0; }

// The material type a kernel for queue Q sees as a compile-time constant (TypeOf in bsdf.h);
// MaterialType::kCount (read the material's own) in the kernel of every queue.
template <uint32_t Q>
constexpr MaterialType kQueueType =
    Q < kEscapedQueue ? QueueMaterialType(Q) : MaterialType::kCount;

// Whether a kernel of feature class C can shade queue q: the class's materials, textures only
// in the general class. The scene's class admits every queue the scene uses.
constexpr bool ClassAdmitsQueue(FeatureClass c, uint32_t q) {
  if (q == kEscapedQueue) return true;
  if (q >= kEscapedQueue) return false;
  MaterialType t = QueueMaterialType(q);
  switch (c) {
    case FeatureClass::kDiffuse:
      return !QueueTextured(q) && (t == MaterialType::kDiffuse || t == MaterialType::kEmissive);
    case FeatureClass::kSmooth:
      return !QueueTextured(q) && t != MaterialType::kPlastic && t != MaterialType::kGltfPbr;
    default: return true;
  }
}

// Whether queue q's materials can need the layered variant's BSDF (src/materials/
// gltf_layered_sample.h): glTF materials, and conductors with energy compensation.
constexpr bool QueueMayBeLayered(uint32_t q) {
  return q < kEscapedQueue && (QueueMaterialType(q) == MaterialType::kGltfPbr ||
                               QueueMaterialType(q) == MaterialType::kConductor);
}

// "diffuse", "gltf_pbr_textured", "escaped", ... (statistics).
const char* ShadeQueueName(uint32_t q);

}  // namespace pt
