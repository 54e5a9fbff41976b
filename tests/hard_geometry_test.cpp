// Hard geometric cases, part 1: grazing incidence on triangles, quads, planes and spheres,
// down to 1e-6 rad. References are exact (double) answers for the float inputs; all rays come
// from fixed-seed generators, so every assertion is deterministic (false-alarm probability 0).
#include <gtest/gtest.h>

#include "tests/hard_geometry_util.h"

namespace pt {
namespace {

using namespace pt::hard;

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
TEST_P(HardLayout, GrazingRaysHitAxisAlignedTrianglesAndQuadsDownTo1e6Rad) {
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
TEST_P(HardLayout, GrazingRaysHitSmallDistantFloorTriangles) {
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
TEST_P(HardLayout, TessellatedFloorNearTheHorizonHasNoHoles) {
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
  Scene scene = BuildScene(std::move(desc), LayoutOptions());
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
TEST_P(HardLayout, GrazingRaysOnRotatedPlanesWithinTheConditionBound) {
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
TEST_P(HardLayout, GrazingRaysAtSphereSilhouettes) {
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

INSTANTIATE_TEST_SUITE_P(Layouts, HardLayout,
                         testing::Values(BvhLayout::kBinary, BvhLayout::kWide),
                         [](const testing::TestParamInfo<BvhLayout>& info) {
                           return std::string(BvhLayoutName(info.param));
                         });

}  // namespace
}  // namespace pt
