// Host-side media tables the renderer derives from a built Scene, and the command line's
// quick atmosphere (--fog).
#pragma once

#include <vector>

#include "src/scene/scene.h"

namespace pt {

// Each primitive's medium interface in BVH order (the camera's medium resolved where an
// object's exterior defaulted to it); empty when no object has an interior. *invisible: how
// many are invisible (rays pass through them).
std::vector<uint32_t> BuildPrimMedia(const Scene& scene, uint32_t* invisible);

// Fills the space the camera is in with a homogeneous, non-absorbing, isotropic medium of
// scattering coefficient sigmaS (per unit length, every channel), replacing the scene's own
// top-level "medium" (objects' default exteriors follow it).
void ApplyFog(float sigmaS, SceneDesc* desc);

}  // namespace pt
