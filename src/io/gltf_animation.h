// glTF animations posed at one time: the chosen animation's channels, sampled (LINEAR with
// spherical interpolation of rotations, STEP, CUBICSPLINE as the specification's Hermite
// spline with tangents scaled by the keyframe interval), set the targeted nodes' translation,
// rotation, scale and morph weights before the meshes, cameras and lights are read, so skins,
// morph targets, cameras and lights all follow. Without a choice the file's static pose stays.
#pragma once

#include <optional>
#include <string>

namespace tinygltf {
class Model;
}  // namespace tinygltf

namespace pt {

// Which animation poses a file, and when: the command line's --animation and --time, or a
// JSON scene's "animation" and "time" beside a glTF file.
struct GltfAnimationChoice {
  // An index, a name, or "all" (every animation at once, as viewers play a file whose parts
  // each have their own); "" = animation 0 (when a time is given).
  std::string animation;
  std::optional<double> time;  // seconds; unset while an animation is named: its start
  bool Active() const { return time.has_value() || !animation.empty(); }
};

struct GltfPoseReport {
  bool posed = false;   // an animation was applied
  std::string warning;  // one line when the time lies outside the clip (clamped), else ""
};

// Poses the model's nodes by the chosen animation (nothing when the choice is not active or the
// file has no animation and none is named). Throws std::runtime_error naming the part
// ("animations[1].samplers[0].output: ...") for malformed animation data, and listing the
// file's animations for an unknown selector.
GltfPoseReport ApplyGltfAnimation(tinygltf::Model& model, const GltfAnimationChoice& choice);

}  // namespace pt
