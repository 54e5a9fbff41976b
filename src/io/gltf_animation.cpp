#include "src/io/gltf_animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "src/io/gltf_accessors.h"

namespace pt {
namespace {

[[noreturn]] void AnimationFail(const std::string& what) { throw std::runtime_error(what); }

std::string Seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g s", t);
  return text;
}

enum class Interpolation { kLinear, kStep, kCubic };

// One sampler's keyframes: times, and per keyframe `width` values (x3 for CUBICSPLINE: the
// in-tangent, the value, the out-tangent).
struct Keyframes {
  std::vector<double> times, values;
  Interpolation interpolation = Interpolation::kLinear;
  int width = 0;

  const double* At(size_t key, int which) const {  // which: 0 in-tangent, 1 value, 2 out-tangent
    size_t element = interpolation == Interpolation::kCubic ? 3 * key + size_t(which) : key;
    return &values[element * size_t(width)];
  }
};

Keyframes ReadKeyframes(const tinygltf::Model& model, const tinygltf::AnimationSampler& s,
                        int width, int components, const std::string& part) {
  Keyframes k;
  k.width = width;
  if (s.interpolation == "STEP") k.interpolation = Interpolation::kStep;
  else if (s.interpolation == "CUBICSPLINE") k.interpolation = Interpolation::kCubic;
  else if (s.interpolation != "LINEAR") {
    AnimationFail(part + ".interpolation: \"" + s.interpolation +
                  "\" is not LINEAR, STEP or CUBICSPLINE");
  }
  try {
    k.times = ReadAccessor(model, s.input, 1);
  } catch (const std::runtime_error& e) {
    AnimationFail(part + ".input: " + e.what());
  }
  if (k.times.empty()) AnimationFail(part + ".input: no keyframes");
  for (size_t i = 0; i < k.times.size(); ++i) {
    if (!std::isfinite(k.times[i]) || (i > 0 && k.times[i] < k.times[i - 1])) {
      AnimationFail(part + ".input: keyframe times must be finite and increasing (time " +
                    std::to_string(i) + ")");
    }
  }
  try {
    k.values = ReadAccessor(model, s.output, components);
  } catch (const std::runtime_error& e) {
    AnimationFail(part + ".output: " + e.what());
  }
  size_t perKey = size_t(width / components) * (k.interpolation == Interpolation::kCubic ? 3 : 1);
  size_t elements = k.values.size() / size_t(components), expected = k.times.size() * perKey;
  if (elements != expected) {
    AnimationFail(part + ".output: " + std::to_string(elements) + " elements for " +
                  std::to_string(k.times.size()) + " keyframes (expected " + std::to_string(expected) +
                  (k.interpolation == Interpolation::kCubic ? ": in-tangent, value, out-tangent each" : "") +
                  ")");
  }
  return k;
}

// The shortest-arc spherical interpolation of two unit quaternions (x, y, z, w).
void Slerp(const double* a, const double* b, double u, double* out) {
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  double sign = d < 0.0 ? -1.0 : 1.0;
  d = std::fabs(d);
  double wa = 1.0 - u, wb = u;
  if (d < 0.9995) {  // nearly equal: linear, normalised below
    double theta = std::acos(std::min(d, 1.0));
    wa = std::sin((1.0 - u) * theta) / std::sin(theta);
    wb = std::sin(u * theta) / std::sin(theta);
  }
  for (int c = 0; c < 4; ++c) out[c] = wa * a[c] + wb * sign * b[c];
}

void Normalize4(std::vector<double>& q) {
  double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (len > 0.0) {
    for (double& c : q) c /= len;
  }
}

// The sampler's value at time t (clamped to its keyframes).
std::vector<double> Sample(const Keyframes& k, double t, bool rotation) {
  size_t n = k.times.size();
  std::vector<double> out(size_t(k.width));
  auto copy = [&](const double* v) { std::copy(v, v + k.width, out.begin()); };
  if (n == 1 || t <= k.times[0]) {
    copy(k.At(0, 1));
  } else if (t >= k.times[n - 1]) {
    copy(k.At(n - 1, 1));
  } else {
    size_t i = size_t(std::upper_bound(k.times.begin(), k.times.end(), t) - k.times.begin()) - 1;
    double dt = k.times[i + 1] - k.times[i], u = (t - k.times[i]) / dt;
    const double *v0 = k.At(i, 1), *v1 = k.At(i + 1, 1);
    if (k.interpolation == Interpolation::kStep) {
      copy(v0);
    } else if (k.interpolation == Interpolation::kLinear && rotation) {
      Slerp(v0, v1, u, out.data());
    } else if (k.interpolation == Interpolation::kLinear) {
      for (int c = 0; c < k.width; ++c) out[size_t(c)] = v0[c] + u * (v1[c] - v0[c]);
    } else {  // Hermite: p0, m0 = dt * out-tangent(i), p1, m1 = dt * in-tangent(i + 1)
      double u2 = u * u, u3 = u2 * u;
      double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
      const double *b0 = k.At(i, 2), *a1 = k.At(i + 1, 0);
      for (int c = 0; c < k.width; ++c) {
        out[size_t(c)] = h00 * v0[c] + h10 * dt * b0[c] + h01 * v1[c] + h11 * dt * a1[c];
      }
    }
  }
  if (rotation) Normalize4(out);
  return out;
}

std::string DescribeAnimations(const tinygltf::Model& model) {
  std::string list;
  for (size_t i = 0; i < model.animations.size(); ++i) {
    list += (list.empty() ? "" : ", ") + std::to_string(i);
    if (!model.animations[i].name.empty()) list += " \"" + model.animations[i].name + "\"";
  }
  return list.empty() ? "none" : list;
}

// The animation a selector names: "" is 0; digits an index; otherwise a name.
size_t SelectAnimation(const tinygltf::Model& model, const std::string& selector) {
  bool numeric = !selector.empty() && selector.size() <= 9 &&
                 selector.find_first_not_of("0123456789") == std::string::npos;
  for (size_t i = 0; i < model.animations.size(); ++i) {
    if (selector.empty() || (numeric && std::stoul(selector) == i) ||
        (!numeric && model.animations[i].name == selector)) {
      return i;
    }
  }
  AnimationFail("no animation " + (numeric ? selector : "\"" + selector + "\"") +
                " in the file (animations: " + DescribeAnimations(model) + ")");
}

// How many morph targets the node's mesh has (what a weights channel animates).
int MorphTargetCount(const tinygltf::Model& model, const tinygltf::Node& node) {
  if (node.mesh < 0 || size_t(node.mesh) >= model.meshes.size()) return 0;
  const tinygltf::Mesh& mesh = model.meshes[size_t(node.mesh)];
  return mesh.primitives.empty() ? 0 : int(mesh.primitives[0].targets.size());
}

void ApplyChannel(tinygltf::Model& model, const tinygltf::Animation& a, size_t c, double t,
                  const std::string& part) {
  const tinygltf::AnimationChannel& ch = a.channels[c];
  std::string chPart = part + ".channels[" + std::to_string(c) + "]";
  const std::string& path = ch.target_path;
  if (path != "translation" && path != "rotation" && path != "scale" && path != "weights") {
    return;  // KHR_animation_pointer and the like: nothing of the pose
  }
  if (ch.target_node < 0 || size_t(ch.target_node) >= model.nodes.size()) {
    AnimationFail(chPart + ".target.node: node " + std::to_string(ch.target_node) + " does not exist");
  }
  if (ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size()) {
    AnimationFail(chPart + ".sampler: sampler " + std::to_string(ch.sampler) + " does not exist");
  }
  tinygltf::Node& node = model.nodes[size_t(ch.target_node)];
  if (!node.matrix.empty()) {
    AnimationFail(chPart + ".target.node: node " + std::to_string(ch.target_node) +
                  " has a matrix, and glTF animates only translation, rotation and scale");
  }
  int width = path == "rotation" ? 4 : path == "weights" ? MorphTargetCount(model, node) : 3;
  if (width == 0) {
    AnimationFail(chPart + ".target.node: node " + std::to_string(ch.target_node) +
                  " has no mesh with morph targets to weigh");
  }
  std::string samplerPart = part + ".samplers[" + std::to_string(ch.sampler) + "]";
  Keyframes k = ReadKeyframes(model, a.samplers[size_t(ch.sampler)], width,
                              path == "weights" ? 1 : width, samplerPart);
  std::vector<double> v = Sample(k, t, path == "rotation");
  if (path == "translation") node.translation = v;
  if (path == "rotation") node.rotation = v;
  if (path == "scale") node.scale = v;
  if (path == "weights") node.weights = v;
}

// [start, end] of the animation: its samplers' first and last keyframe times.
std::pair<double, double> ClipRange(const tinygltf::Model& model, const tinygltf::Animation& a,
                                    const std::string& part) {
  double start = INFINITY, end = -INFINITY;
  for (size_t s = 0; s < a.samplers.size(); ++s) {
    std::vector<double> times;
    try {
      times = ReadAccessor(model, a.samplers[s].input, 1);
    } catch (const std::runtime_error& e) {
      AnimationFail(part + ".samplers[" + std::to_string(s) + "].input: " + e.what());
    }
    if (times.empty()) continue;
    start = std::min(start, times.front());
    end = std::max(end, times.back());
  }
  if (!(start <= end)) AnimationFail(part + ": has no keyframes");
  return {start, end};
}

}  // namespace

GltfPoseReport ApplyGltfAnimation(tinygltf::Model& model, const GltfAnimationChoice& choice) {
  GltfPoseReport report;
  if (!choice.Active() || (model.animations.empty() && choice.animation.empty())) return report;
  bool all = choice.animation == "all";
  std::vector<size_t> chosen;
  for (size_t i = 0; all && i < model.animations.size(); ++i) chosen.push_back(i);
  if (!all) chosen.push_back(SelectAnimation(model, choice.animation));
  double start = INFINITY, end = -INFINITY;
  for (size_t i : chosen) {
    auto [s, e] = ClipRange(model, model.animations[i], "animations[" + std::to_string(i) + "]");
    start = std::min(start, s);
    end = std::max(end, e);
  }
  double t = choice.time.value_or(start);
  if (t < start || t > end) {
    const tinygltf::Animation& a = model.animations[chosen[0]];
    std::string name = all ? std::string("s (all)")
                           : " " + std::to_string(chosen[0]) + (a.name.empty() ? "" : " \"" + a.name + "\"");
    report.warning = "time " + Seconds(t) + " lies outside animation" + name + " (" +
                     Seconds(start) + " to " + Seconds(end) + "): posed at its " +
                     (t < start ? "start" : "end") + ", " + Seconds(std::clamp(t, start, end));
    t = std::clamp(t, start, end);
  }
  for (size_t i : chosen) {  // with "all", a later animation's channel wins on the same target
    const tinygltf::Animation& a = model.animations[i];
    for (size_t c = 0; c < a.channels.size(); ++c) {
      ApplyChannel(model, a, c, t, "animations[" + std::to_string(i) + "]");
    }
  }
  report.posed = true;
  return report;
}

}  // namespace pt
