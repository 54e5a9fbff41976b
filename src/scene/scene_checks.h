// Scenes that render black, or whose lights do nothing, for a reason the user can fix: each
// finding is a warning the app prints before rendering (the render still runs).
#pragma once

#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace pt {

// Finds: no light at all (no emitter with radiance, no point light with intensity, a black
// background); nothing to see (no objects, a black background); an emissive material all of
// whose one-sided surfaces face away from the camera and from every other primitive (it lights
// nothing and is never seen).
std::vector<std::string> DarkSceneWarnings(const Scene& scene);

}  // namespace pt
