// What a ray query returns (compact, stored per path) and the full surface description the
// shade stage rebuilds from it.
#pragma once

#include "src/core/math.h"

namespace pt {

// Closest hit as stored in path state: 16 bytes.
struct HitRecord {
  float t;        // ray parameter (ray directions are unit length, so also distance)
  uint32_t prim;  // index into SceneView::prims; kNoHit when the ray escaped
  vec2 uv;        // triangle: barycentrics (b1, b2); quad: (s, t); sphere: unused

  static constexpr uint32_t kNoHit = 0xffffffffu;
};

struct SurfaceInteraction {
  vec3 p;         // hit point
  vec3 pError;    // conservative absolute error bound on p, per axis
  vec3 ng;        // unit geometric normal, the side the shape calls front
  vec3 ns;        // unit shading normal (interpolated), flipped onto ng's side
  vec2 uv;        // shape parameters: triangle (b1, b2), quad (s, t), sphere (phi, theta)
  uint32_t material;
  int32_t light;  // emitting primitive's light index, or -1
};

// BVH work counters for the statistics.
struct TraversalCounters {
  uint32_t nodes = 0;
  uint32_t prims = 0;
};

}  // namespace pt
