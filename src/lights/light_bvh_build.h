// Host construction of the light BVH (src/lights/light_bvh.h walks it) and the light sampler
// choice.
#pragma once

#include <optional>

#include "src/lights/light_bvh.h"
#include "src/scene/scene.h"

namespace pt {

// What a finite light emits, for the tree: its world box, its orientation cone and phi, an
// intensity scale (W/sr at normal incidence): a point or spot light's intensity on its axis,
// a flat emitter's radiance x area (per side), a sphere's radiance x its cross-section, all as
// luminance and with the emission texture's mean (Scene::lightPower carries it). Importance
// phi cos / d^2 then estimates the irradiance each delivers, so point and area lights compare
// fairly (power, flux, would favour a point light 4x over a flat emitter of equal peak
// intensity). None for lights at infinity and lights of no power (they are never chosen).
std::optional<LightBounds> LightBoundsOf(const Scene& scene, size_t light);

// Builds Scene::lightNodes, lightTrails and lightTree over the finite lights of positive
// power (lights [0, lightTree.boundedCount)), from Scene::lights and lightPower: binned
// splits minimising the surface area orientation heuristic (Conty Estevez and Kulla 2018),
// one light per leaf, at most kLightBvhMaxDepth levels. Records Scene::lightBvhBuildMs.
void BuildLightBvh(Scene& scene);

// Finite lights from which kAuto chooses the BVH (ChooseLightSampler).
constexpr size_t kAutoBvhMinLights = 16;

// The sampler a render uses: `requested`, or for kAuto the BVH where the tree holds at least
// kAutoBvhMinLights lights and power otherwise (a few lights gain little from the tree and
// pay for its walk).
LightSampler ChooseLightSampler(LightSampler requested, const Scene& scene);

const char* LightSamplerName(LightSampler s);

}  // namespace pt
