// The receiver the light BVH sampler weighs lights for, at a surface vertex and again at the
// next vertex: next-event estimation at vertex k chooses a light by its importance at (p_k,
// n_k), and when the BSDF-sampled ray from vertex k hits an emitter, MIS needs that same
// choice probability, so n_k travels in path state (PathState::prevNormal, 4 bytes) and p_k is
// the ray's origin. Other samplers ignore the normal and store nothing.
#pragma once

#include "src/geometry/interaction.h"
#include "src/integrator/path_state.h"
#include "src/lights/light_bvh.h"

namespace pt {

// A tree of one finite light chooses it whatever the receiver (light_bvh.h), so no normal
// is kept for it.
PT_HDI bool UsesLightTree(const SceneView& s) {
  return s.lightTree.sampler == uint32_t(LightSampler::kBvh) && s.lightTree.boundedCount > 1;
}

// Whether a material may scatter light arriving from behind its shading normal (glass, glTF
// transmission): its receiver is two-sided. Only the light choice's efficiency depends on
// this; the estimate stays unbiased either way (light_bvh.h).
PT_HDI bool MayTransmit(const Material& m) {
  if (m.type == MaterialType::kDielectric) return true;
  return m.type == MaterialType::kGltfPbr && (m.transmission > 0.0f || m.transmissionTexture >= 0);
}

// The packed receiver at a surface vertex seen from wo: the shading normal on wo's side.
PT_HDI uint32_t SurfaceReceiver(const SceneView& s, const SurfaceInteraction& si, vec3 wo,
                                const Material& m) {
  if (!UsesLightTree(s)) return kNoReceiver;
  vec3 n = glm::dot(si.ns, wo) < 0.0f ? -si.ns : si.ns;
  return PackReceiver(n, MayTransmit(m));
}

// The reference the light choice saw at the vertex a path's ray left from `origin`. After a
// camera ray or a delta bounce (kFlagSpecular) no light was chosen there and MIS does not
// apply, so nothing is read.
PT_HDI LightRef PrevVertexRef(const SceneView& s, PathState ps, uint32_t id, uint32_t flags,
                              vec3 origin) {
  if (!UsesLightTree(s) || (flags & kFlagSpecular) != 0) return ReceiverRef(origin, kNoReceiver);
  return ReceiverRef(origin, ps.prevNormal[id]);
}

}  // namespace pt
