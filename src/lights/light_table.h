// Host-side construction of the light table: which primitives emit, the point lights and the
// background, and the power-proportional probabilities next-event estimation chooses them by.
#pragma once

#include "src/scene/scene.h"

namespace pt {

// Estimated emitted power (luminance) that the light choice is proportional to.
double LightPower(const Scene& scene, const Light& light);

// Fills scene.lights, scene.lightPmf / lightCdf, scene.backgroundLight, scene.distantLights
// and the environment map's tables (scene.env), and sets PrimRef::light on emitting primitives
// (-1 elsewhere). Expects scene.prims in BVH order with materials set, scene.desc (materials,
// shapes, point and directional lights, background, environment) and the bounding sphere
// scene.sceneCenter / sceneRadius. Light order: area lights in PrimRef order, then point
// lights and directional lights in file order (black ones left out), then the background
// when it is not black, then the environment map when it is not dark.
void BuildLightTable(Scene& scene);

}  // namespace pt
