// Instancing's device structs: a mesh stored once in object space with its own BVH (the bottom
// level), placed any number of times by an Instance (transform, inverse, material override),
// found through a BVH over the instances' world bounds (the top level).
#pragma once

#include "src/core/math.h"

namespace pt {

// An affine map as three rows of a 3x4 matrix: p' = (r0 . (p, 1), r1 . (p, 1), r2 . (p, 1)).
struct Affine3 {
  vec4 r0 = vec4(1.0f, 0.0f, 0.0f, 0.0f);
  vec4 r1 = vec4(0.0f, 1.0f, 0.0f, 0.0f);
  vec4 r2 = vec4(0.0f, 0.0f, 1.0f, 0.0f);

  PT_HDI vec3 Point(vec3 p) const {
    return vec3(r0.x * p.x + r0.y * p.y + r0.z * p.z + r0.w,
                r1.x * p.x + r1.y * p.y + r1.z * p.z + r1.w,
                r2.x * p.x + r2.y * p.y + r2.z * p.z + r2.w);
  }
  PT_HDI vec3 Vector(vec3 v) const {
    return vec3(r0.x * v.x + r0.y * v.y + r0.z * v.z, r1.x * v.x + r1.y * v.y + r1.z * v.z,
                r2.x * v.x + r2.y * v.y + r2.z * v.z);
  }
  // The transpose of the linear part applied to v: with the inverse's rows, maps normals.
  PT_HDI vec3 TransposedVector(vec3 v) const {
    return vec3(r0.x * v.x + r1.x * v.y + r2.x * v.z, r0.y * v.x + r1.y * v.y + r2.y * v.z,
                r0.z * v.x + r1.z * v.y + r2.z * v.z);
  }
  // Per row |r.x p.x| + |r.y p.y| + |r.z p.z| + |r.w|: bounds every partial sum of Point(p).
  PT_HDI vec3 AbsPointSum(vec3 p) const {
    return vec3(fabsf(r0.x * p.x) + fabsf(r0.y * p.y) + fabsf(r0.z * p.z) + fabsf(r0.w),
                fabsf(r1.x * p.x) + fabsf(r1.y * p.y) + fabsf(r1.z * p.z) + fabsf(r1.w),
                fabsf(r2.x * p.x) + fabsf(r2.y * p.y) + fabsf(r2.z * p.z) + fabsf(r2.w));
  }
  // |linear part| applied to a non-negative error vector.
  PT_HDI vec3 AbsVector(vec3 e) const {
    return vec3(fabsf(r0.x) * e.x + fabsf(r0.y) * e.y + fabsf(r0.z) * e.z,
                fabsf(r1.x) * e.x + fabsf(r1.y) * e.y + fabsf(r1.z) * e.z,
                fabsf(r2.x) * e.x + fabsf(r2.y) * e.y + fabsf(r2.z) * e.z);
  }
};

// Bits of Instance::flags.
enum InstanceFlag : uint32_t {
  kInstanceIdentity = 1u << 0,  // toWorld is exactly the identity: rays and hits stay as they are
  kInstanceMirrored = 1u << 1,  // det < 0: world triangles wind the other way round
};

// One placement of a mesh. 128 bytes. The world-space primitives of a scene that has instances
// (quads, spheres, meshes placed once) form one more bottom level, placed by the identity.
struct alignas(16) Instance {
  Affine3 toWorld;      // object -> world
  Affine3 toObject;     // world -> object (the inverse, computed in double)
  uint32_t nodeOffset;  // the mesh's bottom level: its root in nodes / wideNodes
  uint32_t primOffset;  // its first primitive in prims (leaf ranges are relative to it)
  uint32_t mesh;        // index of the mesh (host bookkeeping and messages)
  int32_t material;     // material of every triangle, or -1 for the mesh's own
  int32_t lightBase;    // light index of this placement's first emitter, or -1 (none emits)
  uint32_t flags;       // InstanceFlag bits
  uint32_t firstTriangle;  // the mesh's first triangle in triangles
  uint32_t pad;
};

constexpr uint32_t kNoInstance = 0xffffffffu;

}  // namespace pt
