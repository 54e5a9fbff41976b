// Host-side construction of the light table: which primitives emit, the point lights and the
// background, and the power-proportional probabilities next-event estimation chooses them by.
#pragma once

#include "src/scene/scene.h"

namespace pt {

// Estimated emitted power (luminance) that the light choice is proportional to.
double LightPower(const Scene& scene, const Light& light);

// Fills scene.lights, scene.lightPmf / lightCdf and scene.backgroundLight, and sets
// PrimRef::light on emitting primitives (-1 elsewhere). Expects scene.prims in BVH order with
// materials set, scene.desc (materials, shapes, point lights, background) and the bounding
// sphere scene.sceneCenter / sceneRadius. Light order: each instance's area lights
// (src/scene/instances.h), then the world's in shape order, then point lights in file order,
// then the background when it is not black.
void BuildLightTable(Scene& scene);

// Recomputes scene.lightPower of lights [first, end) (an instance's lights after it moved).
void UpdateLightPowers(Scene& scene, size_t first, size_t end);

// The choice probabilities again from scene.lightPower, the background's recomputed (the
// bounding sphere may have changed). O(lights), no power recomputed but the background's.
void UpdateLightDistribution(Scene& scene);

}  // namespace pt
