// Object transforms of the scene format: a row-major 4x4 `matrix`, or p' = T * Rz * Ry * Rx * S * p
// from `scale`, `rotate` (degrees about world X, then Y, then Z) and `translate`.
#pragma once

#include <array>

#include "src/core/math.h"

namespace pt {

class JsonObject;

// 16 numbers row-major acting on column vectors (translation at 3, 7, 11) -> glm's column-major.
glm::mat4 MatrixFromRowMajor(const std::array<float, 16>& rowMajor);

// T * Rz * Ry * Rx * S. Multiples of 90 degrees give exact 0 and +-1 entries.
glm::mat4 TrsMatrix(vec3 scale, vec3 rotateDegrees, vec3 translate);

// When the linear part is s * (a rotation or reflection), returns true and |s| in *scale.
bool UniformScaleOf(const glm::mat4& m, float* scale);

// Reads a `transform` object (its fields checked, errors naming them); refuses both forms at
// once, a last matrix row other than 0 0 0 1, a zero scale and a singular matrix.
glm::mat4 ParseTransform(const JsonObject& transform);

}  // namespace pt
