// The automatic camera of a scene that brings none (a glTF file without cameras): a
// three-quarter view that frames the scene's bounds whatever the image's aspect ratio.
#pragma once

#include "src/scene/scene.h"

namespace pt {

constexpr float kAutoCameraFovY = 40.0f;          // degrees, vertical
constexpr float kAutoCameraAzimuth = 45.0f;       // degrees from +Z (glTF's front) towards +X
constexpr float kAutoCameraElevation = 30.0f;     // degrees above the horizontal plane
constexpr float kAutoCameraMargin = 1.1f;         // distance factor beyond a tight fit

// The camera looks at the centre c of the bounds [lo, hi] from the direction of the azimuth
// and elevation above, with +Y up, from the distance
//   d = margin * R / sin(h),  R = |hi - lo| / 2 (the bounds' bounding sphere),
// where h is the smaller of the vertical and horizontal half fields of view (the horizontal
// one from the aspect ratio width / height). The bounding sphere then subtends less than h
// from the camera, so every point of the bounds projects inside the image. An empty or
// degenerate box (no extent) is framed as if its radius were 1.
CameraDesc FrameBounds(vec3 lo, vec3 hi, float aspect, float fovYDegrees = kAutoCameraFovY);

}  // namespace pt
