// Host-side construction of the light table: which primitives emit, the point lights and the
// background, and the power-proportional probabilities next-event estimation chooses them by.
#pragma once

#include "src/scene/scene.h"

namespace pt {

// A spot light from its description: the axis normalised, the cone angles as the falloff's
// scale and offset (Light::SpotFalloff).
Light MakeSpotLight(const SpotLightDesc& desc);

// Estimated emitted power (luminance) that the light choice is proportional to.
double LightPower(const Scene& scene, const Light& light);

// Fills scene.lights, scene.lightPower, scene.lightPmf / lightCdf, scene.backgroundLight,
// scene.distantLights and the environment map's tables (scene.env), and sets PrimRef::light on
// emitting primitives (-1 elsewhere). Expects scene.prims in BVH order with materials set,
// scene.desc (materials, shapes, point, spot and directional lights, background, environment)
// and the bounding sphere scene.sceneCenter / sceneRadius. Light order: each instance's area
// lights (src/scene/instances.h), then the world's in shape order, then point lights, spot
// lights and directional lights in file order (black directional lights left out), then the
// background when it is not black, then the environment map when it is not dark.
void BuildLightTable(Scene& scene);

// Recomputes scene.lightPower of lights [first, end) (an instance's lights after it moved).
void UpdateLightPowers(Scene& scene, size_t first, size_t end);

// The choice probabilities again from scene.lightPower, the background's recomputed (the
// bounding sphere may have changed), and the light BVH rebuilt (BuildLightBvh: O(n log n) in
// the finite lights). No power recomputed but the background's.
void UpdateLightDistribution(Scene& scene);

}  // namespace pt
