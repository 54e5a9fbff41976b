// Hard geometric cases ("Hard cases stay numerically stable"): grazing rays, rays through shared
// edges and vertices of meshes far from the origin, rays running inside a surface's plane,
// surfaces 1e-5 apart, and degenerate triangles in OBJ and glTF files.
//
// Every reference answer is computed in double precision from the float inputs exactly as the
// renderer receives them (the float ray and the float shape), so a tolerance only has to cover
// the renderer's own arithmetic; each tolerance below says where it comes from. Nothing here is
// random in the statistical sense: all rays come from fixed-seed generators, so every assertion
// is deterministic (false-alarm probability 0).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <vector>

#include "src/geometry/shapes.h"
#include "src/geometry/traverse.h"
#include "src/integrator/stages/generate.h"
#include "src/io/scene_loader.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"

namespace pt {
namespace {

using glm::dvec3;

constexpr double kEps = 0x1p-24;  // unit roundoff of float (half an ulp of 1)
constexpr double kPiD = 3.14159265358979323846;

std::string Fmt(double v) {  // for RecordProperty: 3 significant digits, any magnitude
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3g", v);
  return buf;
}

// A scene of bare shapes (one diffuse material), built by the renderer's own BuildScene so the
// BVH and the view are exactly what rendering uses.
struct ShapeScene {
  Scene scene;
  SceneView view;
};

ShapeScene BuildShapes(std::vector<Triangle> tris, std::vector<Quad> quads = {},
                       std::vector<Sphere> spheres = {}) {
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
  ShapeScene s{BuildScene(std::move(d)), {}};
  s.view = HostSceneView(s.scene);
  return s;
}

// ---- Exact (double) references for a float ray ----

// Where the float ray o + t d meets the plane through p with normal n (both double).
double ExactPlaneT(const Ray& r, dvec3 p, dvec3 n) {
  return glm::dot(n, p - dvec3(r.o)) / glm::dot(n, dvec3(r.d));
}

// Barycentrics (b0, b1, b2) of q in the float triangle, in double.
dvec3 ExactBarycentrics(const Triangle& tri, dvec3 q) {
  dvec3 p0(tri.p0), e1 = dvec3(tri.p1) - p0, e2 = dvec3(tri.p2) - p0, w = q - p0;
  dvec3 n = glm::cross(e1, e2);
  double nn = glm::dot(n, n);
  double b1 = glm::dot(glm::cross(w, e2), n) / nn;
  double b2 = glm::dot(glm::cross(e1, w), n) / nn;
  return dvec3(1.0 - b1 - b2, b1, b2);
}

double MinComponentD(dvec3 v) { return std::min(v.x, std::min(v.y, v.z)); }

// Unit direction making angle theta with the plane spanned by unit in-plane vectors a (along
// which the ray travels) and the normal n, heading into the plane (against n).
vec3 GrazingDirection(dvec3 a, dvec3 n, double theta) {
  return vec3(glm::normalize(std::cos(theta) * a - std::sin(theta) * n));
}

// ---- Grazing incidence ----

// Floors and walls (axis-aligned planes, the common case: a camera looking along a floor) hit at
// angles down to 1e-6 rad. KNOWN FAILURE for triangles at <= 1e-5 rad until the fix for
// src/geometry/shapes.h described at GrazingRaysHitSmallDistantFloorTriangles is applied. The plane coordinate of every vertex is exact, so the renderer's
// offsets p - o are exact across the plane and the problem stays well conditioned: the
// triangle's t = sum(e_i z_i) / sum(e_i) with all e_i > 0 inside, each e_i accurate to a few
// roundings of its own size, and the quad's t = dot(n, origin - o) / dot(n, d) with two
// non-zero products. Tolerance: 64 unit roundoffs times (1 + D / size), where D is the ray's
// length and size the shape's (the shear multiplies the vertex offsets, up to D + size, into
// the edge functions whose scale is size) - 1.2e-5 relative for the rays below.
TEST(HardGeometry, GrazingRaysHitAxisAlignedTrianglesAndQuadsDownTo1e6Rad) {
  const float y0 = 0.25f;  // the plane y = y0
  Triangle tri{vec3(-1.0f, y0, -1.0f), vec3(1.5f, y0, -0.75f), vec3(-0.5f, y0, 1.25f)};
  Quad quad{vec3(-1.0f, y0, -1.0f), vec3(2.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 2.0f)};
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int tested = 0, failures = 0;
  double worst = 0.0;
  for (double theta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    for (int k = 0; k < 2000; ++k) {
      bool useQuad = k % 2 == 1;
      bool fromBelow = k % 4 >= 2;  // both faces are surfaces: approach from either side
      // A target well inside (a margin of 0.05 of the shape), in double.
      dvec3 target;
      if (useQuad) {
        target = dvec3(quad.origin) + (0.05 + 0.9 * u01(rng)) * dvec3(quad.u) +
                 (0.05 + 0.9 * u01(rng)) * dvec3(quad.v);
      } else {
        double a = u01(rng), b = u01(rng);
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        double b1 = 0.05 + 0.85 * a, b2 = 0.05 + 0.85 * b;
        target = dvec3(tri.p0) + b1 * (dvec3(tri.p1) - dvec3(tri.p0)) +
                 b2 * (dvec3(tri.p2) - dvec3(tri.p0));
      }
      double phi = 2.0 * kPiD * u01(rng);
      dvec3 along(std::cos(phi), 0.0, std::sin(phi));
      dvec3 n(0.0, fromBelow ? -1.0 : 1.0, 0.0);
      vec3 d = GrazingDirection(along, n, theta);
      double dist = 0.5 + 1.5 * u01(rng);
      Ray ray{vec3(target - dist * dvec3(d)), d};
      if (!(fromBelow ? ray.o.y < y0 : ray.o.y > y0)) continue;  // rounded onto the plane
      // The exact hit of this float ray, and whether it is still well inside.
      double tExact = ExactPlaneT(ray, dvec3(0.0, y0, 0.0), dvec3(0.0, 1.0, 0.0));
      dvec3 hitExact = dvec3(ray.o) + tExact * dvec3(ray.d);
      double margin;
      if (useQuad) {
        double s = (hitExact.x - quad.origin.x) / quad.u.x;
        double t = (hitExact.z - quad.origin.z) / quad.v.z;
        margin = std::min(std::min(s, 1.0 - s), std::min(t, 1.0 - t));
      } else {
        margin = MinComponentD(ExactBarycentrics(tri, hitExact));
      }
      if (margin < 0.01) continue;
      ++tested;
      float t = 0.0f;
      vec2 uv;
      bool hit = useQuad ? IntersectQuad(quad, ray, kInfinity, &t, &uv)
                         : IntersectTriangle(tri, ray, kInfinity, &t, &uv);
      double size = 2.0;
      double tol = 64.0 * kEps * (1.0 + dist / size) * tExact;
      double err = hit ? std::fabs(t - tExact) : kInfinity;
      worst = std::max(worst, hit ? err / tExact : 0.0);
      if (!hit || !(err <= tol)) {
        if (++failures <= 5)
          ADD_FAILURE() << (useQuad ? "quad" : "triangle") << " theta " << theta
                        << (hit ? " t " : " missed, exact t ") << t << " vs " << tExact;
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << tested;
  EXPECT_GT(tested, 11000);
  RecordProperty("worst_relative_t_error", Fmt(worst));
}

// The same bug at ordinary angles: small floor triangles (1 cm) seen from 100 units away by a
// camera 0.5 above the floor meet the rays at ~5e-3 rad. The hit is far from any edge and
// t = 100 is ~7 orders of magnitude above its rounding error, yet it must not be lost (a lost
// hit is a hole in a tessellated ground near the horizon). Tolerance as above.
//
// KNOWN FAILURE (bug in src/geometry/shapes.h, IntersectTriangle; see the hard-cases report):
// the t > deltaT test bounds the error of the sheared x' = x + s_x z by gamma(5) (|x'| + |z|),
// i.e. with |s_x| <= 1, where |s_x z| = |d_kx| |z| is the term actually added. For a ray
// nearly parallel to the triangle that makes deltaT ~ 3 gamma(5) D^2 / (theta S) for a
// triangle of size S at distance D - beyond t = D once theta < 9e-7 D / S - and the hit is
// dropped. Fix: deltaX = gamma(5) * (maxXt + |sx / sz| * maxZt), deltaY likewise with sy.
// This test and the one above fail until that fix is applied.
TEST(HardGeometry, GrazingRaysHitSmallDistantFloorTriangles) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int failures = 0, tested = 0;
  for (int k = 0; k < 4000; ++k) {
    double phi = 2.0 * kPiD * u01(rng);
    dvec3 toward(std::cos(phi), 0.0, std::sin(phi));
    dvec3 side(-toward.z, 0.0, toward.x);
    const double size = 0.01, dist = 100.0, height = 0.5;
    // A 1 cm triangle on the floor y = 0, 100 away from the camera's foot.
    dvec3 c = dist * toward;
    Triangle tri{vec3(c - size * toward - size * side), vec3(c + size * toward),
                 vec3(c - size * toward + size * side)};
    for (Triangle* t : {&tri}) t->p0.y = t->p1.y = t->p2.y = 0.0f;
    dvec3 target = (dvec3(tri.p0) + dvec3(tri.p1) + dvec3(tri.p2)) / 3.0 +
                   0.3 * size * (u01(rng) - 0.5) * side;
    vec3 o(0.0f, float(height), 0.0f);
    Ray ray{o, vec3(glm::normalize(target - dvec3(o)))};
    double tExact = ExactPlaneT(ray, dvec3(0.0), dvec3(0.0, 1.0, 0.0));
    if (MinComponentD(ExactBarycentrics(tri, dvec3(ray.o) + tExact * dvec3(ray.d))) < 0.05) continue;
    ++tested;
    float t = 0.0f;
    vec2 uv;
    bool hit = IntersectTriangle(tri, ray, kInfinity, &t, &uv);
    if (!hit || !(std::fabs(t - tExact) <= 64.0 * kEps * (1.0 + dist / size) * tExact)) {
      if (++failures <= 5)
        ADD_FAILURE() << (hit ? "t " : "missed, exact t ") << t << " vs " << tExact;
    }
  }
  EXPECT_EQ(failures, 0) << "of " << tested << " rays at ~5e-3 rad";
  EXPECT_GT(tested, 3000);
}

// The same bug seen in a render: a black floor tessellated into 5 cm triangles, seen from 0.1
// above it at 60 to 200 units (rays meet it at 0.5e-3 to 1.7e-3 rad), under a white sky. A
// pixel whose whole footprint lands on the floor must be exactly 0 (every sample hits the
// black floor); a sample whose floor hit is dropped goes on below the floor to the sky and
// adds 1/4 - a hole. Deterministic (each sample is 0 or 1).
// KNOWN FAILURE until the src/geometry/shapes.h fix above is applied.
TEST(HardGeometry, TessellatedFloorNearTheHorizonHasNoHoles) {
  SceneDesc desc = LoadSceneFromString(R"({
    "render": {"width": 32, "height": 32, "spp": 4, "max_depth": 1, "seed": 1},
    "camera": {"position": [0, 0.1, 0], "look_at": [100, 0, 0], "fov_y": 0.1},
    "background": [1, 1, 1],
    "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
    "objects": []})", "floor-scene.json", ".");
  const double x0 = 60.0, x1 = 200.0, halfZ = 0.25, cell = 0.05;
  const int nx = int((x1 - x0) / cell + 0.5), nz = int(2.0 * halfZ / cell + 0.5);
  auto at = [&](int i, int j) { return vec3(float(x0 + i * cell), 0.0f, float(-halfZ + j * cell)); };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nz; ++j) {
      for (Triangle t : {Triangle{at(i, j), at(i, j + 1), at(i + 1, j + 1)},
                         Triangle{at(i, j), at(i + 1, j + 1), at(i + 1, j)}}) {
        desc.triangles.push_back(t);
        desc.triangleNormals.push_back(TriangleNormals{});
        desc.triangleMaterials.push_back(0);
      }
    }
  Scene scene = BuildScene(std::move(desc));
  RenderResult res = test::RenderOnCpu(scene);
  EXPECT_EQ(res.stats.nonfiniteSamples, 0u);
  int checked = 0, holes = 0;
  for (int py = 0; py < 32; ++py)
    for (int px = 0; px < 32; ++px) {
      bool onFloor = true;  // the footprint is the quadrilateral of its corners' floor points
      for (int c = 0; c < 4; ++c) {
        Ray r = CameraRay(scene.camera, float(px + c % 2), float(py + c / 2), 32.0f, 32.0f, vec2(0.5f));
        double t = -double(r.o.y) / r.d.y;
        dvec3 p = dvec3(r.o) + t * dvec3(r.d);
        onFloor = onFloor && t > 0.0 && p.x > x0 && p.x < x1 && std::fabs(p.z) < halfZ;
      }
      if (!onFloor) continue;
      ++checked;
      float v = res.image.rgb[3 * (size_t(py) * 32 + px)];
      if (v != 0.0f && ++holes <= 5) ADD_FAILURE() << "hole at pixel " << px << "," << py << ": " << v;
    }
  EXPECT_EQ(holes, 0) << "of " << checked << " pixels on the floor";
  EXPECT_GT(checked, 300);
}

// Arbitrarily oriented triangles and quads at angles 1e-1 .. 1e-6. Here the vertex offsets
// p - o round in every axis, which moves the plane by up to ~2 eps |p - o| along its normal:
// the hit of a ray at angle theta is then only defined to within that shift / sin(theta) along
// the plane and to the same relative error in t (the problem's condition number; no float
// algorithm does better). So the test asserts what that allows: a hit whenever the exact hit
// lies farther inside than shift = 16 eps R / sin(theta) (R = the largest |p - o|) and farther
// along the ray than the renderer's own conservative bound on t's error (pbrt-v4's deltaT,
// within which a hit cannot be told from t = 0 and is dropped to avoid self-intersection:
// at most 18 eps R + 66 eps R^3 / (A sin(theta)) for a triangle of area A, and 0 for quads,
// whose plane distance is checked against gamma(6) |n| (|origin| + |o|)); t within 4 shift +
// 64 eps t; never a NaN. At 1e-6 rad only the no-NaN and the t bounds remain (the count of
// asserted hits per angle is recorded).
TEST(HardGeometry, GrazingRaysOnRotatedPlanesWithinTheConditionBound) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> g;
  int failures = 0;
  for (double theta : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
    int hitsRequired = 0;
    for (int k = 0; k < 2000; ++k) {
      // A random plane through a random centre: frame (a, b, n).
      dvec3 n = glm::normalize(dvec3(g(rng), g(rng), g(rng)));
      dvec3 a = glm::normalize(glm::cross(n, dvec3(g(rng), g(rng), g(rng))));
      dvec3 b = glm::cross(n, a);
      dvec3 c(g(rng), g(rng), g(rng));
      bool useQuad = k % 2 == 1;
      Triangle tri{vec3(c - a - b), vec3(c + 1.2 * a - 0.9 * b), vec3(c + 0.1 * a + 1.3 * b)};
      Quad quad{vec3(c - a - b), vec3(2.0 * a), vec3(2.0 * b)};
      // The plane as the renderer stores it (float vertices), in double.
      dvec3 p0 = useQuad ? dvec3(quad.origin) : dvec3(tri.p0);
      dvec3 nf = useQuad ? glm::normalize(glm::cross(dvec3(quad.u), dvec3(quad.v)))
                         : glm::normalize(glm::cross(dvec3(tri.p1) - p0, dvec3(tri.p2) - p0));
      dvec3 target = useQuad ? dvec3(quad.origin) + (0.2 + 0.6 * u01(rng)) * dvec3(quad.u) +
                                   (0.2 + 0.6 * u01(rng)) * dvec3(quad.v)
                             : (dvec3(tri.p0) + dvec3(tri.p1) + dvec3(tri.p2)) / 3.0;
      double phi = 2.0 * kPiD * u01(rng);
      dvec3 along = glm::normalize(std::cos(phi) * glm::cross(nf, a) + std::sin(phi) * glm::cross(nf, b));
      dvec3 side = (k % 4 >= 2) ? -nf : nf;
      vec3 d = GrazingDirection(along, side, theta);
      double dist = 0.5 + u01(rng);
      Ray ray{vec3(target - dist * dvec3(d)), d};
      double tExact = ExactPlaneT(ray, p0, nf);
      double sinTheta = std::fabs(glm::dot(dvec3(ray.d), nf));
      double R = 0.0;
      for (dvec3 p : useQuad ? std::vector<dvec3>{dvec3(quad.origin), dvec3(quad.origin + quad.u),
                                                  dvec3(quad.origin + quad.v),
                                                  dvec3(quad.origin + quad.u + quad.v)}
                             : std::vector<dvec3>{dvec3(tri.p0), dvec3(tri.p1), dvec3(tri.p2)})
        R = std::max(R, glm::length(p - dvec3(ray.o)));
      dvec3 hitExact = dvec3(ray.o) + tExact * dvec3(ray.d);
      double margin;  // distance inside the shape's edges, in scene units
      if (useQuad) {
        dvec3 rel = hitExact - dvec3(quad.origin);
        double s = glm::dot(rel, a) / 2.0, t = glm::dot(rel, b) / 2.0;
        margin = 2.0 * std::min(std::min(s, 1.0 - s), std::min(t, 1.0 - t));
      } else {
        margin = MinComponentD(ExactBarycentrics(tri, hitExact));  // heights here are > 1
      }
      float t = 0.0f;
      vec2 uv(0.0f);
      bool hit = useQuad ? IntersectQuad(quad, ray, kInfinity, &t, &uv)
                         : IntersectTriangle(tri, ray, kInfinity, &t, &uv);
      if (hit && !(std::isfinite(t) && std::isfinite(uv.x) && std::isfinite(uv.y))) {
        ++failures;
        ADD_FAILURE() << "non-finite hit at theta " << theta;
        continue;
      }
      double shift = 16.0 * kEps * R / sinTheta;
      double area = useQuad ? glm::length(glm::cross(dvec3(quad.u), dvec3(quad.v)))
                            : 0.5 * glm::length(glm::cross(dvec3(tri.p1) - dvec3(tri.p0),
                                                           dvec3(tri.p2) - dvec3(tri.p0)));
      double tFloor = useQuad ? 8.0 * Gamma(6) * (glm::length(dvec3(quad.origin)) +
                                                   glm::length(dvec3(ray.o))) / sinTheta
                              : 18.0 * kEps * R + 66.0 * kEps * R * R * R / (area * sinTheta);
      bool mustHit = tExact > tFloor && margin > shift;
      hitsRequired += mustHit;
      if (mustHit && !hit) {
        if (++failures <= 5)
          ADD_FAILURE() << "false miss at theta " << theta << ", margin " << margin << " > "
                        << shift;
        continue;
      }
      if (hit && !(std::fabs(t - tExact) <= 4.0 * shift + 64.0 * kEps * tExact)) {
        if (++failures <= 5)
          ADD_FAILURE() << "t " << t << " vs exact " << tExact << " at theta " << theta;
      }
    }
    RecordProperty("asserted_hits_at_theta_" + std::to_string(theta), hitsRequired);
    if (theta >= 1e-4) {
      EXPECT_GT(hitsRequired, 1500) << "theta " << theta;
    }
  }
  EXPECT_EQ(failures, 0);
}

// Rays passing a sphere at grazing incidence: the angle between the ray and the surface at the
// hit is acos(b / r) for impact parameter b. A float b below r can be no closer than one ulp,
// so angles below ~sqrt(2 eps) = 3.5e-4 rad do not exist for a unit-scale float ray; the test
// sweeps b from r cos(0.1) to the last float below r, plus tangent and just-outside rays.
// The discriminant r^2 - |perp|^2 carries a rounding error up to ~4 gamma(3) r^2 (the squares
// round), so a hit is required when the exact discriminant exceeds 8 gamma(3) r^2, i.e. for
// angles above ~1.2e-3 rad; closer to tangent a hit or a miss are both right, but never a NaN
// or a t off the exact root by more than the condition bound (the root moves by db/sin(angle)
// when b moves by db): 8 gamma(6) (|f| + r) (1 + 1 / sin(angle)).
TEST(HardGeometry, GrazingRaysAtSphereSilhouettes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> g;
  int required = 0, failures = 0;
  double smallestRequiredAngle = 1.0;
  for (int k = 0; k < 20000; ++k) {
    dvec3 c(g(rng) * 10.0, g(rng) * 10.0, g(rng) * 10.0);
    float r = float(0.1 + 10.0 * u01(rng));
    Sphere sph{vec3(c), r};
    dvec3 center(sph.center);
    dvec3 axis = glm::normalize(dvec3(g(rng), g(rng), g(rng)));
    dvec3 off = glm::normalize(glm::cross(axis, dvec3(g(rng), g(rng), g(rng))));
    // Impact parameter: angles 1e-1 .. 1e-4 log-uniform, then a few ulps around tangent.
    double angle = std::pow(10.0, -1.0 - 3.0 * u01(rng));
    double b = k % 5 == 4 ? r * (1.0 + (int(u01(rng) * 9.0) - 4) * kEps) : r * std::cos(angle);
    double dist = r * (1.5 + 3.0 * u01(rng));
    Ray ray{vec3(center + b * off - dist * axis), vec3(axis)};
    // Exact roots of the float ray against the float sphere.
    dvec3 f = dvec3(ray.o) - center, dd(ray.d);
    double dd2 = glm::dot(dd, dd);
    double bb = glm::dot(f, dd) / dd2;
    dvec3 perp = f - bb * dd;
    double disc = double(r) * r - glm::dot(perp, perp);
    float t = 0.0f;
    bool hit = IntersectSphere(sph, ray, kInfinity, &t);
    if (hit && !std::isfinite(t)) {
      ++failures;
      ADD_FAILURE() << "non-finite t";
      continue;
    }
    double r2 = double(r) * r;
    bool mustHit = disc > 8.0 * Gamma(3) * r2;
    bool mustMiss = disc < -8.0 * Gamma(3) * r2;
    if (mustHit) {
      ++required;
      double sinAngle = std::sqrt(disc / r2);
      smallestRequiredAngle = std::min(smallestRequiredAngle, std::asin(sinAngle));
      double tExact = -bb - std::sqrt(disc / dd2);  // in units of the float d, as t is
      double tol = 8.0 * Gamma(6) * (glm::length(f) + r) * (1.0 + 1.0 / sinAngle);
      if (!hit || !(std::fabs(t - tExact) <= tol)) {
        if (++failures <= 5)
          ADD_FAILURE() << "sphere r " << r << " angle " << std::asin(sinAngle)
                        << (hit ? " t " : " missed, exact t ") << t << " vs " << tExact;
      }
    } else if (mustMiss && hit) {
      if (++failures <= 5) ADD_FAILURE() << "spurious hit at disc " << disc / r2;
    } else if (hit) {  // the tangent region: a hit must still be near the tangent point
      double tTangent = -bb;
      if (!(std::fabs(t - tTangent) <= r * 1e-2 + 8.0 * Gamma(6) * glm::length(f))) {
        if (++failures <= 5) ADD_FAILURE() << "tangent hit at t " << t << " vs " << tTangent;
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << required << " required hits";
  EXPECT_GT(required, 9000);
  EXPECT_LT(smallestRequiredAngle, 2e-3);
  RecordProperty("smallest_asserted_sphere_angle", Fmt(smallestRequiredAngle));
}

// ---- Shared edges and vertices far from the origin ----

std::vector<Triangle> Icosphere(dvec3 center, double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<dvec3> v = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (dvec3& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto middle = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = uint32_t(v.size() - 1);
    };
    std::vector<glm::uvec3> next;
    for (glm::uvec3 tri : f) {
      uint32_t a = middle(tri.x, tri.y), b = middle(tri.y, tri.z), c = middle(tri.z, tri.x);
      next.insert(next.end(), {{tri.x, a, c}, {tri.y, b, a}, {tri.z, c, b}, {a, b, c}});
    }
    f = next;
  }
  // Each vertex is rounded to float once, so shared vertices are bit-identical in every triangle.
  std::vector<vec3> vf;
  for (dvec3 p : v) vf.push_back(vec3(center + radius * p));
  std::vector<Triangle> out;
  for (glm::uvec3 tri : f) out.push_back(Triangle{vf[tri.x], vf[tri.y], vf[tri.z]});
  return out;
}

// A closed, tessellated axis-aligned cube whose grid coordinates are each one float.
std::vector<Triangle> TessellatedCube(dvec3 center, double half, int n, std::vector<float> grid[3]) {
  for (int a = 0; a < 3; ++a) {
    grid[a].clear();
    for (int i = 0; i <= n; ++i) grid[a].push_back(float(center[a] - half + 2.0 * half * i / n));
  }
  std::vector<Triangle> out;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          vec3 p[4];
          for (int q = 0; q < 4; ++q) {
            glm::ivec3 idx;
            idx[axis] = side;
            idx[(axis + 1) % 3] = i + (q == 1 || q == 2);
            idx[(axis + 2) % 3] = j + (q >= 2);
            p[q] = vec3(grid[0][idx.x], grid[1][idx.y], grid[2][idx.z]);
          }
          bool flip = (i + j) % 2 == 1;
          out.push_back(flip ? Triangle{p[0], p[1], p[3]} : Triangle{p[0], p[1], p[2]});
          out.push_back(flip ? Triangle{p[1], p[2], p[3]} : Triangle{p[0], p[2], p[3]});
        }
      }
    }
  }
  return out;
}

// Rays from outside aimed exactly at a vertex or at a point of a shared edge (the point rounded
// to float, so it lies within an ulp of the edge), continuing to a point inside: each must
// enter the closed mesh there - never slip through the crack between two triangles to the far
// side or out. The target is exactly on the float mesh; rounding the origin to float moves the
// ray sideways by at most eps |o|_1, which moves the hit along the ray by that times
// (1 + tan(incidence)) < 2 for rays aimed inside the inner ball (incidence < 35 deg); the
// renderer's own rounding of p - o adds a few eps |p - o|. Tolerance: 8 eps |o|_1 + 64 eps dist
// (1.4e-2 at 1e4, against a slip-through error of at least the mesh's chord, > 0.5 radius).
int TraceAtEdges(const ShapeScene& s, const std::vector<Triangle>& tris, dvec3 center,
                 double innerRadius, int rays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> g;
  std::uniform_int_distribution<size_t> pick(0, tris.size() - 1);
  int failures = 0;
  for (int i = 0; i < rays; ++i) {
    const Triangle& tri = tris[pick(rng)];
    const vec3 corner[3] = {tri.p0, tri.p1, tri.p2};
    int e = int(u01(rng) * 3.0) % 3;
    dvec3 target = i % 4 == 0 ? dvec3(corner[e])
                              : glm::mix(dvec3(corner[e]), dvec3(corner[(e + 1) % 3]), u01(rng));
    dvec3 inner = center + glm::normalize(dvec3(g(rng), g(rng), g(rng))) *
                               (innerRadius * std::cbrt(u01(rng)));
    double dist = 0.05 * innerRadius + 3.0 * innerRadius * u01(rng);
    vec3 o = vec3(target + glm::normalize(target - inner) * dist);
    Ray ray{o, vec3(glm::normalize(target - dvec3(o)))};
    double expected = glm::length(target - dvec3(o));
    double tol = 8.0 * kEps * (std::fabs(o.x) + std::fabs(o.y) + std::fabs(o.z)) + 64.0 * kEps * dist;
    HitRecord hit;
    bool ok = IntersectClosest(s.view, ray, kInfinity, &hit, nullptr) &&
              std::fabs(hit.t - expected) <= tol;
    if (i % 8 == 0) ok = ok && IntersectAny(s.view, ray, kInfinity, nullptr);
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << "ray " << i << " hit " << hit.prim << " t " << hit.t << " vs " << expected
                    << " (tol " << tol << ")";
  }
  return failures;
}

TEST(HardGeometry, WatertightAtSharedEdgesOfMeshesFarFromTheOrigin) {
  // Unit-size and kilometre-size meshes at offset 1e4 (float spacing there is ~1e-3) and 1e5.
  struct Case { dvec3 center; double radius; };
  for (Case c : {Case{dvec3(1e4, -1e4, 1e4), 1.0}, Case{dvec3(1e4, 1e4, -1e4), 1e3},
                 Case{dvec3(-1e5, 2e5, 1e5), 50.0}}) {
    std::vector<Triangle> sphere = Icosphere(c.center, c.radius, 4);
    ShapeScene s = BuildShapes(sphere);
    EXPECT_EQ(TraceAtEdges(s, sphere, c.center, 0.5 * c.radius, 40000, 11), 0)
        << "icosphere at " << c.center.x << " radius " << c.radius;
  }
  dvec3 center(1e4 + 0.3, -1e4 + 0.7, 1e4 - 0.2);
  std::vector<float> grid[3];
  std::vector<Triangle> cube = TessellatedCube(center, 1.0, 12, grid);
  ShapeScene s = BuildShapes(cube);
  EXPECT_EQ(TraceAtEdges(s, cube, center, 0.8, 40000, 12), 0);

  // Axis-aligned rays exactly through the grid's vertices and along its edges' lines, where the
  // edge functions are exactly 0 and the double-precision fallback decides: every one must hit
  // the first face at the grid coordinate. face - o is exact (Sterbenz), and t = sum(e_i z) /
  // sum(e_i) rounds a few times: within 8 eps relative.
  int failures = 0, rays = 0;
  for (int axis = 0; axis < 3; ++axis) {
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int i = 0; i <= 12; ++i) {
      for (int j = 0; j <= 12; ++j) {
        for (int dir : {-1, 1}) {
          vec3 o, d(0.0f);
          o[axis] = float(center[axis] - 5.0 * dir);
          o[a1] = grid[a1][i];
          o[a2] = grid[a2][j];
          d[axis] = float(dir);
          float face = dir > 0 ? grid[axis].front() : grid[axis].back();
          HitRecord hit;
          ++rays;
          bool ok = IntersectClosest(s.view, Ray{o, d}, kInfinity, &hit, nullptr);
          double expected = std::fabs(double(face) - double(o[axis]));
          ok = ok && std::fabs(hit.t - expected) <= 8.0 * kEps * expected;
          if (!ok && ++failures <= 5)
            ADD_FAILURE() << "axis " << axis << " grid " << i << "," << j << " t " << hit.t;
        }
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << rays;
}

// ---- Rays inside a surface's plane ----

// Rays running exactly inside the plane of a tessellated floor (along its grid lines, through
// its vertices and across its triangles) must not report the floor - every triangle and quad
// is seen edge-on, det = 0 - and must still find the sphere resting on it, at the right t,
// with no NaN anywhere. The same for rays spawned from a floor point along the tangent plane.
TEST(HardGeometry, RaysInsideASurfacePlaneReportNoSpuriousHits) {
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    std::vector<Triangle> floor;
    const int n = 8;
    auto at = [&](int i, int j) { return vec3(scale * (-4.0f + i), 0.0f, scale * (-4.0f + j)); };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        floor.push_back(Triangle{at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        floor.push_back(Triangle{at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      }
    Quad quadFloor{vec3(-4.0f * scale, 0.0f, 5.0f * scale), vec3(8.0f * scale, 0, 0),
                   vec3(0, 0, 3.0f * scale)};
    Sphere ball{vec3(0.0f, scale, 0.0f), scale};  // touches the floor at the origin
    ShapeScene s = BuildShapes(floor, {quadFloor}, {ball});
    int failures = 0, rays = 0;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < 4000; ++k) {
      // Origins in the plane y = 0: grid vertices, grid lines, or anywhere; directions along
      // grid lines, diagonals or arbitrary, all with d.y = 0 exactly.
      vec3 o(scale * 6.0f * u(rng), 0.0f, scale * 6.0f * u(rng));
      if (k % 3 == 0) o = at(int(4 + 4 * u(rng)), int(4 + 4 * u(rng)));
      if (k % 3 == 1) o.x = at(int(4 + 4 * u(rng)), 0).x;
      vec3 d;
      if (k % 4 == 0) d = vec3(k % 8 == 0 ? 1.0f : -1.0f, 0.0f, 0.0f);
      else if (k % 4 == 1) d = vec3(0.0f, 0.0f, k % 8 == 1 ? 1.0f : -1.0f);
      else if (k % 4 == 2) d = glm::normalize(vec3(1.0f, 0.0f, k % 8 == 2 ? 1.0f : -1.0f));
      else d = glm::normalize(vec3(u(rng), 0.0f, u(rng)));
      d.y = 0.0f;
      if (!(glm::length(d) > 0.5f)) continue;
      HitRecord hit;
      ++rays;
      bool any = IntersectAny(s.view, Ray{o, d}, kInfinity, nullptr);
      bool found = IntersectClosest(s.view, Ray{o, d}, kInfinity, &hit, nullptr);
      bool ok = found == any &&
                (!found || (std::isfinite(hit.t) && std::isfinite(hit.uv.x) &&
                            std::isfinite(hit.uv.y)));
      if (found) {
        // Only the ball may be hit: at its touching point (the origin), which lies in the plane.
        PrimRef ref = s.view.prims[hit.prim];
        dvec3 p = dvec3(o) + double(hit.t) * dvec3(d);
        ok = ok && ref.Type() == ShapeType::kSphere &&
             glm::length(p) <= 1e-3 * scale + 16.0 * kEps * glm::length(dvec3(o));
      }
      if (!ok && ++failures <= 5)
        ADD_FAILURE() << "scale " << scale << " ray " << k << " found " << found << " any " << any
                      << " t " << hit.t;
    }
    EXPECT_EQ(failures, 0) << "of " << rays << " at scale " << scale;

    // Rays 1 ulp above the floor, aimed at the ball's centre height: must hit the ball first.
    HitRecord hit;
    vec3 o(-3.5f * scale, NextFloatUp(0.0f), 0.0f);
    ASSERT_TRUE(IntersectClosest(s.view, Ray{o, vec3(1, 0, 0)}, kInfinity, &hit, nullptr));
    EXPECT_EQ(s.view.prims[hit.prim].Type(), ShapeType::kSphere);
    o.y = scale;
    ASSERT_TRUE(IntersectClosest(s.view, Ray{o, vec3(1, 0, 0)}, kInfinity, &hit, nullptr));
    EXPECT_NEAR(hit.t, 2.5f * scale, 1e-5f * scale);

    // A ray spawned from a floor hit along the tangent plane (dot(w, n) == 0) leaves from
    // above the floor and never re-hits it.
    for (int k = 0; k < 200; ++k) {
      Ray down{vec3(scale * 3.0f * u(rng), scale, scale * 3.0f * u(rng) - 0.0f), vec3(0, -1, 0)};
      if (glm::length(vec2(down.o.x, down.o.z)) < 1.5f * scale) continue;  // not above the ball
      ASSERT_TRUE(IntersectClosest(s.view, down, kInfinity, &hit, nullptr));
      SurfaceInteraction si = MakeInteraction(s.view, down, hit);
      vec3 w = glm::normalize(vec3(u(rng), 0.0f, u(rng)));
      vec3 origin = OffsetRayOrigin(si.p, si.pError, si.ng, w);
      EXPECT_TRUE(IsFinite(origin));
      HitRecord again;
      bool found = IntersectClosest(s.view, Ray{origin, w}, kInfinity, &again, nullptr);
      if (found) {
        EXPECT_EQ(s.view.prims[again.prim].Type(), ShapeType::kSphere) << "scale " << scale;
      }
    }
  }
}

// ---- Surfaces 1e-5 apart (relative to the scene's size) ----

// The exact (double) distance along a float ray to the float primitive hit.record names: its
// plane for a triangle or quad, its nearest root beyond the origin for a sphere.
double ExactT(const ShapeScene& s, const Ray& ray, const HitRecord& hit) {
  PrimRef ref = s.view.prims[hit.prim];
  const SceneDesc& d = s.scene.desc;
  if (ref.Type() == ShapeType::kQuad) {
    const Quad& q = d.quads[ref.Index()];
    return ExactPlaneT(ray, dvec3(q.origin), glm::cross(dvec3(q.u), dvec3(q.v)));
  }
  if (ref.Type() == ShapeType::kTriangle) {
    const Triangle& t = d.triangles[ref.Index()];
    return ExactPlaneT(ray, dvec3(t.p0),
                       glm::cross(dvec3(t.p1) - dvec3(t.p0), dvec3(t.p2) - dvec3(t.p0)));
  }
  const Sphere& sp = d.spheres[ref.Index()];
  dvec3 f = dvec3(ray.o) - dvec3(sp.center), dd(ray.d);
  double a = glm::dot(dd, dd), b = glm::dot(f, dd) / a;
  double c = (glm::dot(f, f) - double(sp.radius) * sp.radius) / a;
  double root = std::sqrt(std::max(0.0, b * b - c));
  return -b - root > 0.0 ? -b - root : -b + root;
}

// Two parallel quads, two parallel (tilted) triangles and two concentric spheres whose surfaces
// are 1e-5 * size apart, at sizes 1e-3, 1 and 1e4 and at offsets from the origin up to the size
// itself (the gap must exceed the float spacing of the coordinates: 1e-5 of a size at an
// offset of the size is ~170 ulps). From outside, the upper surface is hit first; from that
// hit (origin pushed through by OffsetRayOrigin), the lower one is next; from the lower one
// going back up, the upper one. Each t must match the exact distance along the float ray to
// within 5% of the gap: t's own rounding is a few eps * size (< 0.5% of the gap), while
// hitting the wrong surface is off by the whole gap.
TEST(HardGeometry, SurfacesOneHundredThousandthApartStayDistinct) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int failures = 0, checks = 0;
  for (double size : {1e-3, 1.0, 1e4}) {
    for (double offset : {0.0, 0.37, 1.0}) {
      double gap = 1e-5 * size;
      dvec3 base = dvec3(0.3, 0.6, -0.8) * offset * size;
      const dvec3 triNormal = glm::normalize(dvec3(0.2, 1.0, 0.1));
      const dvec3 triCenter = base + dvec3(3.0 * size, 0.0, 0.0);
      float yLo = float(base.y), yHi = float(base.y + gap);
      std::vector<Quad> quads;
      std::vector<Triangle> tris;
      for (int upper = 0; upper < 2; ++upper) {
        float y = upper ? yHi : yLo;
        quads.push_back(Quad{vec3(float(base.x - size), y, float(base.z - size)),
                             vec3(float(2 * size), 0, 0), vec3(0, 0, float(2 * size))});
        dvec3 c = triCenter + (upper ? gap : 0.0) * triNormal;
        dvec3 a = glm::normalize(glm::cross(triNormal, dvec3(0, 0, 1))), b = glm::cross(a, triNormal);
        tris.push_back(Triangle{vec3(c - size * a - size * b), vec3(c + size * a - size * b),
                                vec3(c + size * b)});
      }
      dvec3 sc = base + dvec3(-3.0 * size, 0.0, 0.0);
      std::vector<Sphere> spheres = {Sphere{vec3(sc), float(size)},
                                     Sphere{vec3(sc), float(size + gap)}};
      ShapeScene s = BuildShapes(tris, quads, spheres);
      auto isUpper = [&](const HitRecord& h) {
        PrimRef r = s.view.prims[h.prim];
        switch (r.Type()) {
          case ShapeType::kQuad: return s.scene.desc.quads[r.Index()].origin.y == yHi;
          case ShapeType::kTriangle: return r.Index() == 1;
          default: return s.scene.desc.spheres[r.Index()].radius > float(size);
        }
      };
      auto fail = [&](int which, const char* what, double t, double exact) {
        if (++failures <= 8)
          ADD_FAILURE() << "size " << size << " offset " << offset << " shape " << which << ": "
                        << what << " (t " << t << ", exact " << exact << ", gap " << gap << ")";
      };
      for (int k = 0; k < 300; ++k) {
        int which = k % 3;  // 0 quads, 1 triangles, 2 spheres
        dvec3 n, target;
        if (which == 0) {
          n = dvec3(0, 1, 0);
          target = base + dvec3((u01(rng) - 0.5) * size, 0.0, (u01(rng) - 0.5) * size);
        } else if (which == 1) {
          n = triNormal;
          target = triCenter + 0.3 * size * dvec3(u01(rng) - 0.5, 0.0, u01(rng) - 0.5);
          target -= glm::dot(target - triCenter, n) * n;
        } else {
          n = glm::normalize(dvec3(u01(rng) - 0.5, 1.0, u01(rng) - 0.5));
          target = sc + size * n;
        }
        dvec3 tilt = glm::normalize(glm::cross(n, dvec3(1, 0, 0)));
        dvec3 dirIn = glm::normalize(-n + (u01(rng) * 1.5) * tilt);  // 0..56 deg off the normal
        Ray ray{vec3(target - 0.5 * size * dirIn), vec3(dirIn)};
        ++checks;
        HitRecord h1;
        if (!IntersectClosest(s.view, ray, kInfinity, &h1, nullptr) || !isUpper(h1)) {
          fail(which, "the upper surface is not hit first", h1.t, 0.0);
          continue;
        }
        SurfaceInteraction si = MakeInteraction(s.view, ray, h1);
        Ray through{OffsetRayOrigin(si.p, si.pError, si.ng, ray.d), ray.d};
        HitRecord h2;
        if (!IntersectClosest(s.view, through, kInfinity, &h2, nullptr) || isUpper(h2)) {
          fail(which, "the lower surface is not next", h2.t, 0.0);
          continue;
        }
        double exact2 = ExactT(s, through, h2);
        if (!(std::fabs(h2.t - exact2) <= 0.05 * gap)) fail(which, "lower t", h2.t, exact2);
        SurfaceInteraction lo = MakeInteraction(s.view, through, h2);
        vec3 up = vec3(glm::normalize(n + 0.3 * (u01(rng) - 0.5) * tilt));
        Ray back{OffsetRayOrigin(lo.p, lo.pError, lo.ng, up), up};
        HitRecord h3;
        if (!IntersectClosest(s.view, back, kInfinity, &h3, nullptr) || !isUpper(h3)) {
          fail(which, "going up does not hit the upper surface", h3.t, 0.0);
          continue;
        }
        double exact3 = ExactT(s, back, h3);
        if (!(std::fabs(h3.t - exact3) <= 0.05 * gap)) fail(which, "upper t", h3.t, exact3);
        if (!(h3.t * glm::dot(dvec3(up), n) <= 1.5 * gap)) fail(which, "not the gap", h3.t, gap);
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << checks;
}

// ---- Degenerate triangles in mesh files ----

void CheckBvhFinite(const Scene& scene) {
  ASSERT_FALSE(scene.nodes.empty());
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    const BvhNode& n = scene.nodes[i];
    ASSERT_TRUE(IsFinite(n.boundsMin) && IsFinite(n.boundsMax)) << "node " << i;
    ASSERT_TRUE(n.boundsMin.x <= n.boundsMax.x && n.boundsMin.y <= n.boundsMax.y &&
                n.boundsMin.z <= n.boundsMax.z)
        << "node " << i;
  }
  for (const Triangle& t : scene.desc.triangles)
    ASSERT_TRUE(IsFinite(t.p0) && IsFinite(t.p1) && IsFinite(t.p2));
}

// Renders the scene small and checks the non-finite firewall never fired.
void CheckRendersFinite(const Scene& scene) {
  RenderResult r = test::RenderOnCpu(scene);
  EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
  for (float v : r.image.rgb) ASSERT_TRUE(std::isfinite(v));
  double sum = 0.0;
  for (float v : r.image.rgb) sum += v;
  EXPECT_GT(sum, 0.0);  // the valid triangles are there and lit
}

constexpr const char* kMeshSceneJson = R"({
  "render": {"width": 16, "height": 16, "spp": 4, "max_depth": 3, "seed": 1},
  "camera": {"position": [0.5, 0.5, 4], "look_at": [0.5, 0.5, 0], "fov_y": 40},
  "background": [1, 1, 1],
  "materials": {"m": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
  "objects": [{"type": "mesh", "file": "FILE", "material": "m"}]
})";

std::string SceneFor(const std::string& file) {
  std::string s = kMeshSceneJson;
  s.replace(s.find("FILE"), 4, file);
  return s;
}

// OBJ: zero area (repeated vertex), collinear, all three the same, an exactly collinear sliver
// with large coordinates, overflowing coordinates (1e39 reads as float inf) and mixed +-inf
// (inf - inf = NaN in the edges). tinyobjloader has no syntax for NaN ("nan" reads as 0), so the
// NaN case is in the glTF below. Two good triangles (a unit square) survive.
TEST(HardGeometry, DegenerateObjTrianglesAreSkippedAndCounted) {
  std::string dir = test::TempDir();
  std::ofstream(dir + "/degenerate.obj") << R"(# degenerate faces among good ones
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 3 0 0
v 1e39 0 0
v -1e39 1e39 0
v 100000 100000 100000
v 200000 200000 200000
v 300000 300000 300000
f 1 2 3
f 1 3 4
f 1 2 2
f 1 2 5
f 2 5 6
f 3 3 3
f 1 2 7
f 7 8 3
f 9 10 11
)";
  SceneDesc desc = LoadSceneFromString(SceneFor("degenerate.obj"), "obj-scene.json", dir);
  EXPECT_EQ(desc.skippedDegenerateTriangles, 7);
  EXPECT_EQ(desc.triangles.size(), 2u);
  bool warned = false;
  for (const std::string& w : desc.warnings)
    warned = warned || (w.find("7 degenerate") != std::string::npos &&
                        w.find("degenerate.obj") != std::string::npos);
  EXPECT_TRUE(warned) << "no warning names the count and the file";
  Scene scene = BuildScene(std::move(desc));
  CheckBvhFinite(scene);
  CheckRendersFinite(scene);
}

void Append(std::vector<char>& bin, const void* data, size_t bytes) {
  const char* p = static_cast<const char*>(data);
  bin.insert(bin.end(), p, p + bytes);
}

// glTF: the same kinds plus NaN coordinates, as binary floats, indexed by uint16.
TEST(HardGeometry, DegenerateGltfTrianglesAreSkippedAndCounted) {
  std::string dir = test::TempDir();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float positions[] = {
      0, 0, 0,   1, 0, 0,   1, 1, 0,    0, 1, 0,      // 0-3: a unit square
      2, 0, 0,   3, 0, 0,                             // 4-5: collinear with 0, 1
      nan, 0, 0, 0, nan, 1, 0, 0, nan,                // 6-8: NaN coordinates
      inf, 0, 0, -inf, 1, 0, 0, 0, inf,               // 9-11: infinite coordinates
      3e38f, 0, 0, 0, 3e38f, 0,                       // 12-13: finite, but the area overflows
  };
  const uint16_t indices[] = {0, 1, 2,  0, 2, 3,                  // good
                              0, 1, 1,  0, 1, 4,  1, 4, 5,        // repeated, collinear
                              2, 2, 2,                            // one point
                              0, 1, 6,  6, 7, 8,  2, 3, 7,        // NaN
                              0, 1, 9,  9, 10, 11, 3, 10, 2,      // inf
                              0, 12, 13};                         // overflowing normal
  const int skipped = 11;
  std::vector<char> bin;
  Append(bin, positions, sizeof(positions));
  Append(bin, indices, sizeof(indices));
  while (bin.size() % 4) bin.push_back(0);
  std::ofstream(dir + "/d.bin", std::ios::binary).write(bin.data(), std::streamsize(bin.size()));
  size_t vertexCount = sizeof(positions) / 12, indexCount = sizeof(indices) / 2;
  std::ofstream(dir + "/d.gltf") << R"({
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": )" + std::to_string(vertexCount) +
                                        R"(, "type": "VEC3"},
      {"bufferView": 1, "componentType": 5123, "count": )" + std::to_string(indexCount) +
                                        R"(, "type": "SCALAR"}],
    "bufferViews": [
      {"buffer": 0, "byteOffset": 0, "byteLength": )" + std::to_string(sizeof(positions)) + R"(},
      {"buffer": 0, "byteOffset": )" + std::to_string(sizeof(positions)) +
                                        R"(, "byteLength": )" + std::to_string(sizeof(indices)) +
                                        R"(}],
    "buffers": [{"uri": "d.bin", "byteLength": )" + std::to_string(bin.size()) + R"(}]})";
  SceneDesc desc = LoadSceneFromString(SceneFor("d.gltf"), "gltf-scene.json", dir);
  EXPECT_EQ(desc.skippedDegenerateTriangles, skipped);
  EXPECT_EQ(desc.triangles.size(), 2u);
  bool warned = false;
  for (const std::string& w : desc.warnings)
    warned = warned || (w.find(std::to_string(skipped) + " degenerate") != std::string::npos &&
                        w.find("d.gltf") != std::string::npos);
  EXPECT_TRUE(warned) << "no warning names the count and the file";
  Scene scene = BuildScene(std::move(desc));
  CheckBvhFinite(scene);
  CheckRendersFinite(scene);
}

}  // namespace
}  // namespace pt
