// Host-side construction of the lights at infinity: the environment map's frame and sampling
// distribution (built once, read by src/lights/env_map.h on either backend), and directional
// lights from their descriptions.
#pragma once

#include "src/scene/scene.h"

namespace pt {

// The map's rotation (map frame -> world): Rz * Ry * Rx of the degrees, as object transforms.
mat3 EnvironmentRotation(vec3 rotateDegrees);

// Fills scene.env (size, frame, strength, camera visibility; light index left at -1) and the
// row and column cdfs of texel luminance x solid angle, accumulated in double and rounded
// once, so each probability is the float width of its interval and a texel of zero radiance
// has probability exactly 0. Without a map only the camera visibility is set.
void BuildEnvironmentMap(Scene& scene);

// The integral of the map's luminance over the sphere (strength included): 0 for a dark map.
double EnvironmentMapLuminanceIntegral(const Scene& scene);

// A directional light from its description (direction turned and irradiance scaled with the
// environment when it is part of it).
Light MakeDirectionalLight(const DirectionalLightDesc& desc, const EnvironmentDesc& env);

}  // namespace pt
