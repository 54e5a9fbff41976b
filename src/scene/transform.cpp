#include "src/scene/transform.h"

#include <cmath>

#include "src/io/scene_json.h"

namespace pt {
namespace {

// sin and cos of an angle in degrees, exact at multiples of 90 so axis-aligned rotations stay
// axis-aligned bit for bit.
void SinCosDegrees(double degrees, double* s, double* c) {
  double reduced = std::fmod(degrees, 360.0);
  if (reduced < 0) reduced += 360.0;
  if (reduced == 0.0) { *s = 0; *c = 1; return; }
  if (reduced == 90.0) { *s = 1; *c = 0; return; }
  if (reduced == 180.0) { *s = 0; *c = -1; return; }
  if (reduced == 270.0) { *s = -1; *c = 0; return; }
  double radians = reduced * (3.14159265358979323846 / 180.0);
  *s = std::sin(radians);
  *c = std::cos(radians);
}

// Right-handed rotation about a world axis (0 = X, 1 = Y, 2 = Z).
glm::dmat3 AxisRotation(int axis, double degrees) {
  double s, c;
  SinCosDegrees(degrees, &s, &c);
  glm::dmat3 r(1.0);  // glm is column-major: r[col][row]
  int a = (axis + 1) % 3, b = (axis + 2) % 3;
  r[a][a] = c;
  r[b][a] = -s;
  r[a][b] = s;
  r[b][b] = c;
  return r;
}

vec3 ReadScale(const JsonObject& t) {
  JsonValue field = t.Field("scale");
  vec3 scale = field.Raw().is_array() ? field.Vec3() : vec3(field.Number());
  for (int i = 0; i < 3; ++i) {
    if (scale[i] != 0.0f) continue;
    JsonValue bad = field.Raw().is_array() ? field.Element(i) : field;
    bad.Fail("0 is not a valid scale (it must be non-zero)");
  }
  return scale;
}

glm::mat4 ReadMatrix(const JsonObject& t) {
  JsonValue field = t.Field("matrix");
  if (field.ArraySize() != 16) {
    field.Fail("expected 16 numbers (row-major 4x4), got " + std::to_string(field.ArraySize()));
  }
  std::array<float, 16> m;
  for (size_t i = 0; i < 16; ++i) m[i] = field.Element(i).Number();
  if (m[12] != 0.0f || m[13] != 0.0f || m[14] != 0.0f || m[15] != 1.0f) {
    field.Fail("the last row must be 0 0 0 1, got " + FormatNumber(m[12]) + " " +
               FormatNumber(m[13]) + " " + FormatNumber(m[14]) + " " + FormatNumber(m[15]));
  }
  return MatrixFromRowMajor(m);
}

}  // namespace

glm::mat4 MatrixFromRowMajor(const std::array<float, 16>& rowMajor) {
  glm::mat4 m(1.0f);
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 4; ++col) m[col][row] = rowMajor[row * 4 + col];
  }
  return m;
}

glm::mat4 TrsMatrix(vec3 scale, vec3 rotateDegrees, vec3 translate) {
  glm::dmat3 rotation = AxisRotation(2, rotateDegrees.z) * AxisRotation(1, rotateDegrees.y) *
                        AxisRotation(0, rotateDegrees.x);
  glm::dmat3 linear = rotation * glm::dmat3(glm::dvec3(scale.x, 0, 0), glm::dvec3(0, scale.y, 0),
                                            glm::dvec3(0, 0, scale.z));
  glm::mat4 m = glm::mat4(glm::mat3(linear));
  m[3] = vec4(translate, 1.0f);
  return m;
}

bool UniformScaleOf(const glm::mat4& m, float* scale) {
  glm::dmat3 a = glm::dmat3(glm::mat3(m));
  glm::dmat3 gram = glm::transpose(a) * a;  // s^2 * I exactly when a = s * orthogonal
  double s2 = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
  if (!(s2 > 0.0) || !std::isfinite(s2)) return false;
  // Float rotations are orthogonal to ~1e-7; hand-written ones (0.866, 0.5) to ~1e-4.
  constexpr double kTolerance = 1e-3;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double expected = (i == j) ? s2 : 0.0;
      if (std::fabs(gram[i][j] - expected) > kTolerance * s2) return false;
    }
  }
  *scale = static_cast<float>(std::sqrt(s2));
  return true;
}

glm::mat4 ParseTransform(const JsonObject& t) {
  t.AllowOnly({"matrix", "scale", "rotate", "translate"}, "a transform");
  bool hasMatrix = t.Has("matrix");
  for (const char* key : {"scale", "rotate", "translate"}) {
    if (hasMatrix && t.Has(key)) {
      t.Fail(key, std::string("\"matrix\" and \"") + key +
                      "\" cannot be combined: use the matrix or scale/rotate/translate");
    }
  }
  glm::mat4 m(1.0f);
  if (hasMatrix) {
    m = ReadMatrix(t);
  } else {
    vec3 scale = t.Has("scale") ? ReadScale(t) : vec3(1.0f);
    m = TrsMatrix(scale, t.Vec3Or("rotate", vec3(0.0f)), t.Vec3Or("translate", vec3(0.0f)));
  }
  double det = glm::determinant(glm::dmat3(glm::mat3(m)));
  if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) {
    t.Fail(hasMatrix ? "matrix" : "scale", "the transform is singular or not finite (determinant " +
                                               FormatNumber(det) + ")");
  }
  return m;
}

}  // namespace pt
