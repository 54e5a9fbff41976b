// Scenes that render black, or whose lights do nothing, for a reason the user can fix: each
// finding is a warning the app prints before rendering (the render still runs).
#pragma once

#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

// Finds: no light at all (no emitter with radiance, no point light with intensity, no sun or
// environment map, a black background); nothing to see (no objects, and camera rays that
// escape see black); an emissive material all of
// whose one-sided surfaces face away from the camera and from every other primitive (it lights
// nothing and is never seen).
std::vector<std::string> DarkSceneWarnings(const Scene& scene);

// A pixel whose every channel is below this linear radiance is black in an 8-bit sRGB image
// (it encodes below half a level), and an image is "nearly black" from this share of them.
constexpr float kBlackPixelRadiance = 0.5f / 255.0f / 12.92f;
constexpr double kBlackImageFraction = 0.95;

// After a render: when the finished image (linear RGB, 3 floats a pixel) is nearly black, a
// warning with the share of black pixels and the likely cause (no light; lights too weak for
// the output; no environment and the lights on the far side; the camera inside an object).
// environmentRemovedBy names what removed the environment ("--env none"), if anything.
std::string BlackImageWarning(const Scene& scene, const std::vector<float>& rgb,
                              const std::string& environmentRemovedBy);

}  // namespace pt
