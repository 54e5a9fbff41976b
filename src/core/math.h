// Vector maths shared by host and device: GLM types plus the few helpers rendering needs
// (error bounds, luminance, orthonormal frames). All PT_HD so tests can call them.
#pragma once

#include "src/core/pt.h"

// GLM_FORCE_CTOR_INIT is defined for every target by CMake: a per-header define would give
// translation units that include glm first a different vec3 (a silent ABI mismatch).
#include <glm/glm.hpp>

#include <cfloat>
#include <cmath>
#include <cstring>

namespace pt {

// The C++ overloads (CUDA supplies device versions of these too).
using std::isfinite;
using std::isinf;
using std::isnan;

using glm::vec2;
using glm::vec3;
using glm::vec4;
using glm::mat3;
using glm::mat4;

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv4Pi = 0.07957747154594766788f;
constexpr float kInfinity = INFINITY;
constexpr float kMachineEpsilon = FLT_EPSILON * 0.5f;

// Higham's gamma(n) = n*eps / (1 - n*eps): bound on the relative error of n float operations.
PT_HDI constexpr float Gamma(int n) {
  return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon);
}

template <typename T>
PT_HDI constexpr T Sqr(T x) { return x * x; }

PT_HDI float SafeSqrt(float x) { return sqrtf(fmaxf(0.0f, x)); }
PT_HDI float Clamp01(float x) { return fminf(fmaxf(x, 0.0f), 1.0f); }
PT_HDI float MaxComponent(vec3 v) { return fmaxf(v.x, fmaxf(v.y, v.z)); }
PT_HDI float MinComponent(vec3 v) { return fminf(v.x, fminf(v.y, v.z)); }
PT_HDI int MaxDimension(vec3 v) { return (v.x > v.y) ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2); }
PT_HDI vec3 Abs(vec3 v) { return vec3(fabsf(v.x), fabsf(v.y), fabsf(v.z)); }
PT_HDI bool IsBlack(vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }
PT_HDI bool IsFinite(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

// Rec. 709 luminance of linear RGB.
PT_HDI float Luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Orthonormal basis around a unit normal (Duff et al. 2017, branchless and exact at the poles).
struct Frame {
  vec3 x, y, z;

  PT_HDI static Frame FromZ(vec3 n) {
    float sign = copysignf(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.x = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.y = vec3(b, sign + n.y * n.y * a, -n.y);
    f.z = n;
    return f;
  }
  PT_HDI vec3 ToLocal(vec3 v) const { return vec3(glm::dot(v, x), glm::dot(v, y), glm::dot(v, z)); }
  PT_HDI vec3 FromLocal(vec3 v) const { return v.x * x + v.y * y + v.z * z; }
};

// Next representable float up / down (for conservative bounds and origin offsets).
PT_HDI float NextFloatUp(float v) {
  if (isinf(v) && v > 0.0f) return v;
  if (v == -0.0f) v = 0.0f;
  uint32_t ui;
  memcpy(&ui, &v, sizeof(ui));
  ui = (v >= 0) ? ui + 1 : ui - 1;
  memcpy(&v, &ui, sizeof(v));
  return v;
}

PT_HDI float NextFloatDown(float v) {
  if (isinf(v) && v < 0.0f) return v;
  if (v == 0.0f) v = -0.0f;
  uint32_t ui;
  memcpy(&ui, &v, sizeof(ui));
  ui = (v > 0) ? ui - 1 : ui + 1;
  memcpy(&v, &ui, sizeof(v));
  return v;
}

}  // namespace pt
