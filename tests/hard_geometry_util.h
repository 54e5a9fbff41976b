// Shared pieces of the hard geometric cases: a scene of bare shapes built by BuildScene, and
// exact double-precision references for float rays.
#pragma once


#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "src/geometry/shapes.h"
#include "src/geometry/traverse.h"
#include "src/integrator/stages/generate.h"
#include "src/io/scene_loader.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt::hard {

using glm::dvec3;

constexpr double kEps = 0x1p-24;  // unit roundoff of float (half an ulp of 1)
constexpr double kPiD = 3.14159265358979323846;

inline std::string Fmt(double v) {  // for RecordProperty: 3 significant digits, any magnitude
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

// The geometric cases run once per BVH layout: TEST_P(HardLayout, ...) sets the layout that
// BuildShapes (and LayoutOptions) build for the test's duration.
inline BvhLayout& LayoutUnderTest() {
  static BvhLayout layout = BvhLayout::kBinary;
  return layout;
}

inline BvhBuildOptions LayoutOptions() {
  BvhBuildOptions o;
  o.layout = LayoutUnderTest();
  return o;
}

class HardLayout : public testing::TestWithParam<BvhLayout> {
 protected:
  void SetUp() override { LayoutUnderTest() = GetParam(); }
  void TearDown() override { LayoutUnderTest() = BvhLayout::kBinary; }
};

// A scene of bare shapes (one diffuse material), built by the renderer's own BuildScene so the
// BVH and the view are exactly what rendering uses.
struct ShapeScene {
  Scene scene;
  SceneView view;
};

inline ShapeScene BuildShapes(std::vector<Triangle> tris, std::vector<Quad> quads = {},
                              std::vector<Sphere> spheres = {},
                              const BvhBuildOptions& options = LayoutOptions()) {
  SceneDesc d;
  d.render.width = d.render.height = 1;
  d.render.spp = 1;
  Material m;
  m.albedo = vec3(0.5f);
  d.materials.push_back(m);
  d.materialNames.push_back("m");
  d.triangleNormals.resize(tris.size());
  d.triangleMaterials.assign(tris.size(), 0);
  d.triangles = std::move(tris);
  d.quadMaterials.assign(quads.size(), 0);
  d.quads = std::move(quads);
  d.sphereMaterials.assign(spheres.size(), 0);
  d.spheres = std::move(spheres);
  ShapeScene s{BuildScene(std::move(d), options), {}};
  s.view = HostSceneView(s.scene);
  return s;
}

// ---- Exact (double) references for a float ray ----

// Where the float ray o + t d meets the plane through p with normal n (both double).
inline double ExactPlaneT(const Ray& r, dvec3 p, dvec3 n) {
  return glm::dot(n, p - dvec3(r.o)) / glm::dot(n, dvec3(r.d));
}

// Barycentrics (b0, b1, b2) of q in the float triangle, in double.
inline dvec3 ExactBarycentrics(const Triangle& tri, dvec3 q) {
  dvec3 p0(tri.p0), e1 = dvec3(tri.p1) - p0, e2 = dvec3(tri.p2) - p0, w = q - p0;
  dvec3 n = glm::cross(e1, e2);
  double nn = glm::dot(n, n);
  double b1 = glm::dot(glm::cross(w, e2), n) / nn;
  double b2 = glm::dot(glm::cross(e1, w), n) / nn;
  return dvec3(1.0 - b1 - b2, b1, b2);
}

inline double MinComponentD(dvec3 v) { return std::min(v.x, std::min(v.y, v.z)); }

// Unit direction making angle theta with the plane spanned by unit in-plane vectors a (along
// which the ray travels) and the normal n, heading into the plane (against n).
inline vec3 GrazingDirection(dvec3 a, dvec3 n, double theta) {
  return vec3(glm::normalize(std::cos(theta) * a - std::sin(theta) * n));
}


}  // namespace pt::hard
