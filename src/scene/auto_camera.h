// The automatic camera of a scene that brings none (a glTF file without cameras): the model
// seen from its front, glTF's +Z, looking towards -Z with +Y up (as the Khronos sample viewer
// shows a model), framed to the scene's bounds whatever the image's aspect ratio.
#pragma once

#include "src/scene/scene.h"

namespace pt {

constexpr float kAutoCameraFovY = 40.0f;          // degrees, vertical
constexpr float kAutoCameraMargin = 1.1f;         // distance factor beyond a tight fit

// The camera looks at the centre c of the bounds [lo, hi] along -Z from c + (0, 0, d). With
// half extents (hx, hy, hz) and tx, ty the tangents of the horizontal and vertical half fields
// of view (tx = ty * aspect, aspect = width / height):
//   d = max(hz + margin * max(hx / tx, hy / ty), margin * |(hx, hy, hz)|).
// The first term is the tightest distance at which every corner of the box projects within
// 1 / margin of the image's centre-to-edge distance (the nearest face's corners are the
// widest); the second keeps the camera outside the bounds' sphere for boxes seen end on (a
// rod along Z). An empty or degenerate box (no extent) is framed as the cube c +- (1, 1, 1).
CameraDesc FrameBounds(vec3 lo, vec3 hi, float aspect, float fovYDegrees = kAutoCameraFovY);

// d above, for half extents and the half fields' tangents (tests check the rule with it).
double AutoCameraDistance(glm::dvec3 half, double tanHalfX, double tanHalfY);

}  // namespace pt
