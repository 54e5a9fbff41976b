// Path state as structure-of-arrays: one array per field, indexed by path slot. Stages run
// over a queue of slot indices, so compaction and sorting reorder 4-byte indices and never
// move path data. A slot's numbers depend only on its (pixel, sample), never on its queue
// position, which keeps renders bit-identical across compaction and sort settings.
#pragma once

#include "src/core/atomic.h"
#include "src/core/math.h"
#include "src/geometry/interaction.h"
#include "src/scene/instance_types.h"
#include "src/scene/scene.h"

namespace pt {

// Bits of PathState::flags.
constexpr uint32_t kDepthMask = 0xfffu;        // bounces taken so far
constexpr uint32_t kFlagAlive = 1u << 12;
constexpr uint32_t kFlagSpecular = 1u << 13;   // the last bounce was a delta lobe (or camera)
constexpr uint32_t kFlagShadow = 1u << 14;     // a shadow ray is queued for this bounce
constexpr uint32_t kMediumShift = 15;          // dielectric material index + 1 the path is inside
// The loaders' limits (src/scene/scene.h) fit: a depth never carries into the flags, and every
// material index + 1 fits above them.
static_assert(uint32_t(kMaxBounces) <= kDepthMask, "depth field narrower than kMaxBounces");
static_assert(kMaxMaterials <= (uint64_t(1) << (32 - kMediumShift)) - 1, "medium field too narrow");

PT_HDI uint32_t DepthOf(uint32_t flags) { return flags & kDepthMask; }
PT_HDI bool IsAlive(uint32_t flags) { return (flags & kFlagAlive) != 0; }
PT_HDI int32_t MediumOf(uint32_t flags) { return int32_t(flags >> kMediumShift) - 1; }
PT_HDI uint32_t WithMedium(uint32_t flags, int32_t material) {
  return (flags & ((1u << kMediumShift) - 1)) | (uint32_t(material + 1) << kMediumShift);
}

// A HitRecord as path state keeps it (16 bytes): the instance, where there are instances, is
// in PathState::hitInstance.
struct PathHit {
  float t;
  uint32_t prim;
  vec2 uv;
};

// Raw pointers to the arrays, captured by value in every stage.
struct PathState {
  vec3* rayOrigin;
  vec3* rayDir;
  vec3* throughput;
  vec3* radiance;
  float* prevPdf;    // solid-angle pdf of the BSDF sample that made the current ray
  uint32_t* flags;
  PathHit* hit;
  vec3* shadowOrigin;
  vec3* shadowDir;
  float* shadowTMax;
  vec3* shadowRadiance;  // what the shadow ray adds to radiance if unoccluded
  // First-hit features for denoisers; null unless feature buffers were requested.
  vec3* featureAlbedo;
  vec3* featureNormal;
  float* featureDepth;
  // The emission the camera ray's own hit or escape gave the path (RecordSeenEmission, shade.h):
  // the denoiser can keep it out of what it filters (--denoise-emission keep).
  vec3* featureEmission;
  // The hit's instance; allocated, written and read only in scenes with instances.
  uint32_t* hitInstance;
  // The receiver normal of the vertex the current ray left (PackReceiver), for the light BVH's
  // pmf at an emitter the ray hits; allocated, written and read only under --light-sampler bvh.
  uint32_t* prevNormal = nullptr;
};

// The hit as the intersect stage stores it: its instance only where the scene has instances, so
// a flat scene moves no more bytes than before instancing existed.
PT_HDI void StoreHit(PathState ps, uint32_t id, const HitRecord& hit, bool instanced) {
  ps.hit[id] = PathHit{hit.t, hit.prim, hit.uv};
  if (instanced) ps.hitInstance[id] = hit.instance;
}

PT_HDI HitRecord LoadHit(PathState ps, uint32_t id, bool instanced) {
  PathHit h = ps.hit[id];
  return HitRecord{h.t, h.prim, h.uv, instanced ? ps.hitInstance[id] : kNoInstance};
}

// Bytes per path of the optional feature buffers.
constexpr size_t kFeatureBytes = 3 * sizeof(vec3) + sizeof(float);

// Bytes per path of the arrays above plus the queue and sort key (one uint32 each), and of
// hitInstance (scenes with instances only).
constexpr size_t kPathStateBytes = 4 * sizeof(vec3) + sizeof(float) + sizeof(uint32_t) +
                                   sizeof(PathHit) + 3 * sizeof(vec3) + sizeof(float) +
                                   2 * sizeof(uint32_t);
constexpr size_t kInstanceHitBytes = sizeof(uint32_t);
constexpr size_t kReceiverBytes = sizeof(uint32_t);  // prevNormal, light BVH only

// Integer statistics gathered by the stages.
enum CounterId : uint32_t {
  kCounterShadowRays = 0,
  kCounterNodesVisited,
  kCounterPrimsTested,
  kCounterTraversals,
  kCounterNonfinite,
  kCounterCount,
};

}  // namespace pt
