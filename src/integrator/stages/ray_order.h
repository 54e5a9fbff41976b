// Ray ordering (--ray-order): before a bounce's intersect, a copy of the queue is sorted by a
// key of each path's ray, so that a GPU warp traces rays that start near each other and head
// the same way (they walk the same nodes, in the same child order: the wide traversal orders
// children by the ray's octant). Scattered secondary rays otherwise fill warps at random, and
// a warp runs as long as its longest ray (Meister et al. 2020 survey such keys). The key: the
// direction's octant, then the origin's Morton code in the cube around the scene's bounding
// sphere. Only the order of work changes, never a path's numbers: the image is the same.
#pragma once

#include "src/core/math.h"
#include "src/scene/scene_view.h"

namespace pt {

// 24 bits: three passes of the GPU's 8-bit radix sort. Finished paths (queued only without
// compaction) take the largest key; where they fall among live rays does not matter, they are
// skipped.
constexpr uint32_t kRayOrderKeyBits = 24;
constexpr uint32_t kRayOrderDeadKey = (1u << kRayOrderKeyBits) - 1u;

namespace detail {

// The low 7 bits of v spread to every third bit (bit k to bit 3k).
PT_HDI uint32_t SpreadBits3(uint32_t v) {
  v &= 0x7fu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

PT_HDI uint32_t Cell7(float x) {  // x in [0, 1] to 0..127 (NaN and outside clamp)
  float c = fminf(fmaxf(x * 128.0f, 0.0f), 127.0f);
  return uint32_t(c);
}

}  // namespace detail

// 3 octant bits above a 21-bit Morton code of the origin (7 bits per axis).
PT_HDI uint32_t RayOrderKey(const SceneView& s, vec3 o, vec3 d) {
  const uint32_t octant =
      uint32_t(d.x < 0.0f) | uint32_t(d.y < 0.0f) << 1 | uint32_t(d.z < 0.0f) << 2;
  const float inv = 0.5f / fmaxf(s.sceneRadius, 1e-30f);
  const vec3 u = (o - s.sceneCenter) * inv + vec3(0.5f);
  const uint32_t morton = detail::SpreadBits3(detail::Cell7(u.x)) |
                          detail::SpreadBits3(detail::Cell7(u.y)) << 1 |
                          detail::SpreadBits3(detail::Cell7(u.z)) << 2;
  return octant << 21 | morton;
}

}  // namespace pt
