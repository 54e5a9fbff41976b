// Ray-shape tests with known answers, error bounds checked against double-precision hits, and
// re-intersection of rays spawned with OffsetRayOrigin.
#include <gtest/gtest.h>

#include "tests/stat_test_util.h"

#include <random>

#include "src/geometry/box.h"
#include "src/geometry/shapes.h"

namespace pt {
namespace {

using glm::dvec3;

Ray RayTowards(vec3 o, vec3 target) { return Ray{o, glm::normalize(target - o)}; }

using test::RandomUnit;

// True when every axis of |p - exact| is within pError.
bool ErrorBoxContains(const SurfaceInteraction& si, dvec3 exact) {
  dvec3 diff = glm::abs(dvec3(si.p) - exact);
  return diff.x <= si.pError.x && diff.y <= si.pError.y && diff.z <= si.pError.z;
}

// A SceneView over one shape of each kind (prims 0, 1, 2 = triangle, quad, sphere).
struct OneOfEach {
  Triangle tri;
  TriangleNormals normals{};
  Quad quad;
  Sphere sphere;
  PrimRef prims[3];
  SceneView view;

  OneOfEach() {
    prims[0] = {PrimRef::Pack(ShapeType::kTriangle, 0), 7, -1};
    prims[1] = {PrimRef::Pack(ShapeType::kQuad, 0), 8, 3};
    prims[2] = {PrimRef::Pack(ShapeType::kSphere, 0), 9, -1};
    view.prims = prims;
    view.triangles = &tri;
    view.triangleNormals = &normals;
    view.quads = &quad;
    view.spheres = &sphere;
    view.primCount = 3;
  }
  SurfaceInteraction Interact(uint32_t prim, const Ray& ray, float t, vec2 uv) const {
    return MakeInteraction(view, ray, HitRecord{t, prim, uv});
  }
  // Whether a ray spawned from si towards dir (OffsetRayOrigin) hits prim again.
  bool Rehits(uint32_t prim, const SurfaceInteraction& si, vec3 dir, float* t) const {
    vec2 uv;
    return IntersectPrim(view, prim, Ray{OffsetRayOrigin(si.p, si.pError, si.ng, dir), dir},
                         kInfinity, t, &uv);
  }
};

// ---- Sphere ----

TEST(IntersectionSphere, KnownDistancesAndMisses) {
  Sphere s{vec3(0.0f), 1.0f};
  float t = 0.0f;
  EXPECT_TRUE(IntersectSphere(s, Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, kInfinity, &t));
  EXPECT_FLOAT_EQ(t, 4.0f);
  EXPECT_FALSE(IntersectSphere(s, Ray{vec3(0, 0, 5), vec3(0, 0, 1)}, kInfinity, &t));  // behind
  EXPECT_FALSE(IntersectSphere(s, Ray{vec3(2, 0, 5), vec3(0, 0, -1)}, kInfinity, &t));
  EXPECT_FALSE(IntersectSphere(s, Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, 3.9f, &t));
  EXPECT_FALSE(IntersectSphere(s, Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, 4.0f, &t));  // t < tMax
  EXPECT_TRUE(IntersectSphere(s, Ray{vec3(0, 0, 5), vec3(0, 0, -1)}, 4.001f, &t));

  Sphere off{vec3(1, 2, 3), 0.5f};
  EXPECT_TRUE(IntersectSphere(off, Ray{vec3(1, 2, 10), vec3(0, 0, -1)}, kInfinity, &t));
  EXPECT_FLOAT_EQ(t, 6.5f);
  // Off-centre: the chord at height 0.3 enters at z = 3 + 0.4.
  EXPECT_TRUE(IntersectSphere(off, Ray{vec3(1, 2.3f, 10), vec3(0, 0, -1)}, kInfinity, &t));
  EXPECT_NEAR(t, 6.6f, 1e-5f);
  // From inside: the far root.
  EXPECT_TRUE(IntersectSphere(s, Ray{vec3(0.0f), vec3(0, 1, 0)}, kInfinity, &t));
  EXPECT_FLOAT_EQ(t, 1.0f);
  EXPECT_TRUE(IntersectSphere(s, Ray{vec3(0, 0, 0.5f), vec3(0, 0, 1)}, kInfinity, &t));
  EXPECT_FLOAT_EQ(t, 0.5f);
  EXPECT_TRUE(IntersectSphere(s, Ray{vec3(0, 0, 0.5f), vec3(0, 0, -1)}, kInfinity, &t));
  EXPECT_FLOAT_EQ(t, 1.5f);
  EXPECT_FALSE(IntersectSphere(s, Ray{vec3(0, 0, 0.5f), vec3(0, 0, -1)}, 1.4f, &t));
}

TEST(IntersectionSphere, InteractionBoundsAndSpawnedRays) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  OneOfEach scene;
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    scene.sphere = Sphere{vec3(u(rng), u(rng), u(rng)) * 10.0f, 0.5f + 2.0f * (u(rng) + 1.0f)};
    const Sphere& s = scene.sphere;
    vec3 o = s.center + RandomUnit(rng) * (s.radius * (1.5f + 2.0f * (u(rng) + 1.0f)));
    Ray ray = RayTowards(o, s.center + RandomUnit(rng) * (0.9f * s.radius));
    float t;
    ASSERT_TRUE(IntersectSphere(s, ray, kInfinity, &t));
    ++hits;
    // pError bounds p against the exact reprojection of the same float o + t d onto the sphere.
    SurfaceInteraction si = scene.Interact(2, ray, t, vec2(0.0f));
    dvec3 c(s.center);
    dvec3 exact = c + double(s.radius) * glm::normalize(dvec3(ray.o + t * ray.d) - c);
    EXPECT_TRUE(ErrorBoxContains(si, exact)) << i;
    // The exact ray-sphere hit (near root in double) is close; t's own error moves p along the
    // surface, which pError does not cover (nor need to: it only bounds the distance to it).
    dvec3 f = dvec3(ray.o) - c, d = dvec3(ray.d);
    double b = glm::dot(f, d), cc = glm::dot(f, f) - double(s.radius) * s.radius;
    dvec3 hitExact = dvec3(ray.o) + (-b - std::sqrt(b * b - cc)) * d;
    EXPECT_LT(glm::length(dvec3(si.p) - hitExact), 1e-5 * glm::length(f));
    EXPECT_GT(glm::dot(dvec3(si.ng), exact - c), 0.0);
    EXPECT_NEAR(glm::length(si.ng), 1.0f, 1e-6f);
    EXPECT_EQ(si.material, 9u);

    // Leaving outward never re-hits; going inward hits the far side, not the near one.
    float t2;
    EXPECT_FALSE(scene.Rehits(2, si, glm::normalize(si.ng + RandomUnit(rng) * 0.99f), &t2)) << i;
    vec3 in = glm::normalize(-si.ng + RandomUnit(rng) * 0.99f);
    ASSERT_TRUE(scene.Rehits(2, si, in, &t2)) << i;
    float chord = -2.0f * glm::dot(in, si.ng) * s.radius;
    EXPECT_NEAR(t2, chord, 1e-4f * s.radius) << i;
  }
  EXPECT_EQ(hits, 20000);
}

// ---- Quad ----

TEST(IntersectionQuad, KnownHitsAndMisses) {
  Quad q{vec3(-1, 0, -1), vec3(0, 0, 2), vec3(2, 0, 0)};  // normal cross(u, v) = +y
  float t;
  vec2 st;
  ASSERT_TRUE(IntersectQuad(q, Ray{vec3(0.5f, 3, 0.25f), vec3(0, -1, 0)}, kInfinity, &t, &st));
  EXPECT_FLOAT_EQ(t, 3.0f);
  EXPECT_FLOAT_EQ(st.x, 0.625f);
  EXPECT_FLOAT_EQ(st.y, 0.75f);
  // The back face is hit too (culling is not done here).
  ASSERT_TRUE(IntersectQuad(q, Ray{vec3(0.5f, -2, 0.25f), vec3(0, 1, 0)}, kInfinity, &t, &st));
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_FALSE(IntersectQuad(q, Ray{vec3(1.5f, 3, 0), vec3(0, -1, 0)}, kInfinity, &t, &st));
  EXPECT_FALSE(IntersectQuad(q, Ray{vec3(0, 3, -1.01f), vec3(0, -1, 0)}, kInfinity, &t, &st));
  EXPECT_FALSE(IntersectQuad(q, Ray{vec3(0, 3, 0), vec3(0, 1, 0)}, kInfinity, &t, &st));
  EXPECT_FALSE(IntersectQuad(q, Ray{vec3(0, 1, 0), vec3(1, 0, 0)}, kInfinity, &t, &st));
  EXPECT_FALSE(IntersectQuad(q, Ray{vec3(0, 3, 0), vec3(0, -1, 0)}, 3.0f, &t, &st));
  EXPECT_TRUE(IntersectQuad(q, Ray{vec3(0, 3, 0), vec3(0, -1, 0)}, 3.01f, &t, &st));
  // Edges and corners belong to the quad.
  EXPECT_TRUE(IntersectQuad(q, Ray{vec3(1, 3, 1), vec3(0, -1, 0)}, kInfinity, &t, &st));
  EXPECT_TRUE(IntersectQuad(q, Ray{vec3(-1, 3, 0.3f), vec3(0, -1, 0)}, kInfinity, &t, &st));

  OneOfEach scene;
  scene.quad = q;
  Ray ray = RayTowards(vec3(2, 3, 1), vec3(0.5f, 0, 0.25f));
  ASSERT_TRUE(IntersectQuad(q, ray, kInfinity, &t, &st));
  SurfaceInteraction si = scene.Interact(1, ray, t, st);
  EXPECT_EQ(si.ng, vec3(0, 1, 0));
  EXPECT_EQ(si.ns, vec3(0, 1, 0));
  EXPECT_NEAR(si.p.x, 0.5f, 1e-6f);
  EXPECT_NEAR(si.p.z, 0.25f, 1e-6f);
  EXPECT_EQ(si.material, 8u);
  EXPECT_EQ(si.light, 3);
}

TEST(IntersectionQuad, InteractionBoundsAndSpawnedRays) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  OneOfEach scene;
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    Quad q{vec3(u(rng), u(rng), u(rng)) * 20.0f, RandomUnit(rng) * (0.1f + 3.0f * u01(rng)),
           RandomUnit(rng) * (0.1f + 3.0f * u01(rng))};
    vec3 n = glm::cross(q.u, q.v);
    if (glm::length(n) < 0.1f * glm::length(q.u) * glm::length(q.v)) continue;  // too skewed
    scene.quad = q;
    vec3 target = q.origin + u01(rng) * q.u + u01(rng) * q.v;
    vec3 o = target + RandomUnit(rng) * (0.5f + 5.0f * u01(rng));
    Ray ray = RayTowards(o, target);
    if (fabsf(glm::dot(ray.d, glm::normalize(n))) < 0.2f) continue;  // grazing
    float t;
    vec2 st;
    if (!IntersectQuad(q, ray, kInfinity, &t, &st)) continue;  // target rounded off the edge
    ++checked;
    // pError bounds p against origin + s u + t v evaluated exactly; the exact ray hit is close.
    SurfaceInteraction si = scene.Interact(1, ray, t, st);
    dvec3 exact = dvec3(q.origin) + double(st.x) * dvec3(q.u) + double(st.y) * dvec3(q.v);
    EXPECT_TRUE(ErrorBoxContains(si, exact)) << i;
    dvec3 dn = glm::cross(dvec3(q.u), dvec3(q.v));
    double tExact = glm::dot(dn, dvec3(q.origin) - dvec3(ray.o)) / glm::dot(dn, dvec3(ray.d));
    dvec3 hitExact = dvec3(ray.o) + tExact * dvec3(ray.d);
    EXPECT_LT(glm::length(dvec3(si.p) - hitExact), 1e-5 * (1.0 + glm::length(dvec3(ray.o))));
    // Spawned rays: neither the reflected nor the transmitted one hits the quad again.
    float t2;
    EXPECT_FALSE(scene.Rehits(1, si, glm::reflect(ray.d, si.ng), &t2)) << i;
    EXPECT_FALSE(scene.Rehits(1, si, ray.d, &t2)) << i;
  }
  EXPECT_GT(checked, 10000);
}

// ---- Box (six quads) ----

// Slab test in object space, in double: the reference for a transformed box.
bool ReferenceBoxHit(vec3 lo, vec3 hi, const glm::mat4& toWorld, const Ray& ray, double* t) {
  glm::dmat4 inv = glm::inverse(glm::dmat4(toWorld));
  dvec3 o = dvec3(inv * glm::dvec4(dvec3(ray.o), 1.0));
  dvec3 d = dvec3(inv * glm::dvec4(dvec3(ray.d), 0.0));
  double t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  if (t0 > t1 || t1 <= 0.0) return false;
  *t = t0 > 0.0 ? t0 : t1;
  return true;
}

bool QuadsClosest(const std::vector<Quad>& quads, const Ray& ray, float* t, int* which) {
  float tMax = kInfinity;
  *which = -1;
  for (size_t i = 0; i < quads.size(); ++i) {
    float th;
    vec2 st;
    if (IntersectQuad(quads[i], ray, tMax, &th, &st)) tMax = th, *which = int(i);
  }
  *t = tMax;
  return *which >= 0;
}

void CheckBox(vec3 lo, vec3 hi, const glm::mat4& m, uint32_t seed) {
  std::vector<Quad> quads;
  AppendBoxQuads(lo, hi, m, quads);
  ASSERT_EQ(quads.size(), 6u);
  vec3 center = vec3(m * vec4(0.5f * (lo + hi), 1.0f));
  for (const Quad& q : quads) {
    vec3 faceCenter = q.origin + 0.5f * q.u + 0.5f * q.v;
    EXPECT_GT(glm::dot(glm::cross(q.u, q.v), faceCenter - center), 0.0f);  // outward
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    bool inside = i % 4 == 0;
    vec3 local = inside ? glm::mix(lo, hi, 0.5f + 0.45f * vec3(u(rng), u(rng), u(rng)))
                        : glm::mix(lo, hi, 0.5f + 2.0f * vec3(u(rng), u(rng), u(rng)));
    vec3 o = vec3(m * vec4(local, 1.0f));
    vec3 target =
        vec3(m * vec4(glm::mix(lo, hi, 0.5f + 0.6f * vec3(u(rng), u(rng), u(rng))), 1.0f));
    Ray ray = RayTowards(o, target);
    double tRef;
    float t;
    int which;
    bool ref = ReferenceBoxHit(lo, hi, m, ray, &tRef);
    bool got = QuadsClosest(quads, ray, &t, &which);
    if (ref != got) {
      // Only a ray within rounding of an edge may disagree; none should at these odds.
      ADD_FAILURE() << "ray " << i << " ref " << ref << " got " << got;
      continue;
    }
    if (!ref) continue;
    EXPECT_NEAR(t, tRef, 1e-5 * (1.0 + tRef)) << i;
    // Leaving through a face from inside means the ray points along its outward normal.
    const Quad& q = quads[which];
    float facing = glm::dot(glm::cross(q.u, q.v), ray.d);
    if (inside) {
      EXPECT_GT(facing, 0.0f) << i;
    }
  }
}

TEST(IntersectionBox, IdentityBox) {
  std::vector<Quad> quads;
  AppendBoxQuads(vec3(0.0f), vec3(1.0f), glm::mat4(1.0f), quads);
  ASSERT_EQ(quads.size(), 6u);
  float t;
  int which;
  ASSERT_TRUE(QuadsClosest(quads, Ray{vec3(0.5f, 0.5f, 5.0f), vec3(0, 0, -1)}, &t, &which));
  EXPECT_FLOAT_EQ(t, 4.0f);
  EXPECT_EQ(glm::normalize(glm::cross(quads[which].u, quads[which].v)), vec3(0, 0, 1));
  ASSERT_TRUE(QuadsClosest(quads, Ray{vec3(0.5f, 0.25f, 0.5f), vec3(0, -1, 0)}, &t, &which));
  EXPECT_FLOAT_EQ(t, 0.25f);
  EXPECT_EQ(glm::normalize(glm::cross(quads[which].u, quads[which].v)), vec3(0, -1, 0));
  EXPECT_FALSE(QuadsClosest(quads, Ray{vec3(2.0f, 0.5f, 5.0f), vec3(0, 0, -1)}, &t, &which));
  CheckBox(vec3(0.0f), vec3(1.0f), glm::mat4(1.0f), 1);
}

// T * Ry * S. (No glm/gtc here: every glm include must come after src/core/math.h, which sets
// GLM_FORCE_CTOR_INIT, or vec3 changes ABI between translation units.)
glm::mat4 TranslateRotateYScale(vec3 translate, float degrees, vec3 scale) {
  float c = std::cos(glm::radians(degrees)), s = std::sin(glm::radians(degrees));
  glm::mat4 m(1.0f);  // column-major: m[column][row]
  m[0] = vec4(c * scale.x, 0.0f, -s * scale.x, 0.0f);
  m[1] = vec4(0.0f, scale.y, 0.0f, 0.0f);
  m[2] = vec4(s * scale.z, 0.0f, c * scale.z, 0.0f);
  m[3] = vec4(translate, 1.0f);
  return m;
}

TEST(IntersectionBox, TransformedAndMirrored) {
  glm::mat4 m = TranslateRotateYScale(vec3(-0.4f, 0.0f, -0.3f), 30.0f, vec3(0.6f, 1.2f, 0.9f));
  CheckBox(vec3(-0.5f, 0.0f, -0.5f), vec3(0.5f, 1.0f, 0.5f), m, 2);
  glm::mat4 mirror =
      TranslateRotateYScale(vec3(-0.4f, 0.0f, -0.3f), 30.0f, vec3(-0.6f, 1.2f, 0.9f));
  ASSERT_LT(glm::determinant(glm::mat3(mirror)), 0.0f);
  CheckBox(vec3(-0.5f, 0.0f, -0.5f), vec3(0.5f, 1.0f, 0.5f), mirror, 3);
  // A flat box keeps only its two large faces.
  std::vector<Quad> flat;
  AppendBoxQuads(vec3(0.0f), vec3(1.0f, 0.0f, 1.0f), glm::mat4(1.0f), flat);
  EXPECT_EQ(flat.size(), 2u);
}

// ---- Triangle ----

TEST(IntersectionTriangle, KnownHitsAndMisses) {
  Triangle tri{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};
  float t;
  vec2 b;
  ASSERT_TRUE(IntersectTriangle(tri, Ray{vec3(0.25f, 0.5f, 2), vec3(0, 0, -1)}, kInfinity, &t, &b));
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_FLOAT_EQ(b.x, 0.25f);
  EXPECT_FLOAT_EQ(b.y, 0.5f);
  ASSERT_TRUE(IntersectTriangle(tri, Ray{vec3(0.25f, 0.5f, -3), vec3(0, 0, 1)}, kInfinity, &t, &b));
  EXPECT_FLOAT_EQ(t, 3.0f);  // back face
  EXPECT_FALSE(
      IntersectTriangle(tri, Ray{vec3(0.75f, 0.75f, 2), vec3(0, 0, -1)}, kInfinity, &t, &b));
  EXPECT_FALSE(
      IntersectTriangle(tri, Ray{vec3(0.25f, 0.25f, 2), vec3(0, 0, 1)}, kInfinity, &t, &b));
  EXPECT_FALSE(IntersectTriangle(tri, Ray{vec3(0.25f, 0.25f, 2), vec3(0, 0, -1)}, 2.0f, &t, &b));
  EXPECT_TRUE(IntersectTriangle(tri, Ray{vec3(0.25f, 0.25f, 2), vec3(0, 0, -1)}, 2.001f, &t, &b));
  EXPECT_FALSE(IntersectTriangle(tri, Ray{vec3(0, 0, 2), vec3(1, 0, 0)}, kInfinity, &t, &b));
  // Edges and vertices (exact zeros of the edge functions) hit.
  EXPECT_TRUE(IntersectTriangle(tri, Ray{vec3(0.5f, 0, 2), vec3(0, 0, -1)}, kInfinity, &t, &b));
  EXPECT_TRUE(IntersectTriangle(tri, Ray{vec3(0.5f, 0.5f, 2), vec3(0, 0, -1)}, kInfinity, &t, &b));
  EXPECT_TRUE(IntersectTriangle(tri, Ray{vec3(0, 1, 2), vec3(0, 0, -1)}, kInfinity, &t, &b));
  EXPECT_FLOAT_EQ(b.y, 1.0f);
  // Oblique: from (2, 2, 2) towards (0.2, 0.3, 0).
  Ray ray = RayTowards(vec3(2, 2, 2), vec3(0.2f, 0.3f, 0));
  ASSERT_TRUE(IntersectTriangle(tri, ray, kInfinity, &t, &b));
  EXPECT_NEAR(t, glm::length(vec3(1.8f, 1.7f, 2.0f)), 1e-5f);
  EXPECT_NEAR(b.x, 0.2f, 1e-6f);
  EXPECT_NEAR(b.y, 0.3f, 1e-6f);
}

TEST(IntersectionTriangle, InteractionNormals) {
  OneOfEach scene;
  scene.tri = Triangle{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};  // ng = +z
  Ray ray{vec3(0.25f, 0.25f, 1), vec3(0, 0, -1)};
  SurfaceInteraction si = scene.Interact(0, ray, 1.0f, vec2(0.25f, 0.25f));
  EXPECT_EQ(si.ng, vec3(0, 0, 1));
  EXPECT_EQ(si.ns, si.ng);  // all-zero vertex normals: geometric normal
  EXPECT_EQ(si.p, vec3(0.25f, 0.25f, 0.0f));
  EXPECT_EQ(si.uv, vec2(0.25f, 0.25f));
  EXPECT_EQ(si.material, 7u);
  EXPECT_EQ(si.light, -1);

  vec3 a = glm::normalize(vec3(1, 0, 1)), c = glm::normalize(vec3(0, 1, 1));
  scene.normals = TriangleNormals{vec3(0, 0, 1), a, c};
  si = scene.Interact(0, ray, 1.0f, vec2(0.25f, 0.25f));
  vec3 expect = glm::normalize(0.5f * vec3(0, 0, 1) + 0.25f * a + 0.25f * c);
  EXPECT_NEAR(glm::length(si.ns - expect), 0.0f, 1e-6f);
  // Vertex normals facing away from ng are flipped onto its side.
  scene.normals = TriangleNormals{-vec3(0, 0, 1), -a, -c};
  si = scene.Interact(0, ray, 1.0f, vec2(0.25f, 0.25f));
  EXPECT_NEAR(glm::length(si.ns - expect), 0.0f, 1e-6f);
  // Clockwise winding flips ng.
  scene.tri = Triangle{vec3(0, 0, 0), vec3(0, 1, 0), vec3(1, 0, 0)};
  scene.normals = TriangleNormals{};
  si = scene.Interact(0, ray, 1.0f, vec2(0.25f, 0.25f));
  EXPECT_EQ(si.ng, vec3(0, 0, -1));
  scene.view.triangleNormals = nullptr;
  EXPECT_EQ(scene.Interact(0, ray, 1.0f, vec2(0.25f, 0.25f)).ns, vec3(0, 0, -1));
}

TEST(IntersectionTriangle, InteractionBoundsAndSpawnedRays) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  OneOfEach scene;
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    // Some far from the origin, where pError grows with |p|.
    vec3 base = vec3(u(rng), u(rng), u(rng)) * (i % 2 ? 1000.0f : 2.0f);
    float size = 0.05f + 2.0f * u01(rng);
    Triangle tri{base + RandomUnit(rng) * size, base + RandomUnit(rng) * size,
                 base + RandomUnit(rng) * size};
    vec3 n = glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0);
    if (glm::length(n) < 0.05f * size * size) continue;  // sliver
    scene.tri = tri;
    float b1 = u01(rng), b2 = u01(rng);
    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
    vec3 target = (1.0f - b1 - b2) * tri.p0 + b1 * tri.p1 + b2 * tri.p2;
    Ray ray = RayTowards(target + RandomUnit(rng) * (0.5f + 5.0f * u01(rng)), target);
    if (fabsf(glm::dot(ray.d, glm::normalize(n))) < 0.2f) continue;  // grazing
    float t;
    vec2 bary;
    if (!IntersectTriangle(tri, ray, kInfinity, &t, &bary)) continue;  // rounded off an edge
    ++checked;
    // pError bounds p against sum b_i p_i evaluated exactly (b0 = 1 - b1 - b2 exactly, so the
    // point lies on the triangle); the exact ray hit is close.
    SurfaceInteraction si = scene.Interact(0, ray, t, bary);
    dvec3 p0(tri.p0), e1 = dvec3(tri.p1) - p0, e2 = dvec3(tri.p2) - p0, dn = glm::cross(e1, e2);
    dvec3 exact = p0 + double(bary.x) * e1 + double(bary.y) * e2;
    EXPECT_TRUE(ErrorBoxContains(si, exact)) << i;
    double tExact = glm::dot(dn, p0 - dvec3(ray.o)) / glm::dot(dn, dvec3(ray.d));
    dvec3 hitExact = dvec3(ray.o) + tExact * dvec3(ray.d);
    EXPECT_NEAR(t, tExact, 1e-5 * (1.0 + tExact));
    EXPECT_LT(glm::length(dvec3(si.p) - hitExact), 1e-5 * (1.0 + glm::length(dvec3(ray.o))));
    float t2;
    EXPECT_FALSE(scene.Rehits(0, si, glm::reflect(ray.d, si.ng), &t2)) << i;
    EXPECT_FALSE(scene.Rehits(0, si, ray.d, &t2)) << i;
  }
  EXPECT_GT(checked, 10000);
}

TEST(IntersectionPrim, DispatchesOnType) {
  OneOfEach scene;
  scene.tri = Triangle{vec3(-1, -1, 0), vec3(1, -1, 0), vec3(0, 1, 0)};
  scene.quad = Quad{vec3(-1, -1, -2), vec3(2, 0, 0), vec3(0, 2, 0)};
  scene.sphere = Sphere{vec3(0, 0, -5), 1.0f};
  Ray ray{vec3(0, 0, 3), vec3(0, 0, -1)};
  float t;
  vec2 uv;
  ASSERT_TRUE(IntersectPrim(scene.view, 0, ray, kInfinity, &t, &uv));
  EXPECT_FLOAT_EQ(t, 3.0f);
  ASSERT_TRUE(IntersectPrim(scene.view, 1, ray, kInfinity, &t, &uv));
  EXPECT_FLOAT_EQ(t, 5.0f);
  EXPECT_FLOAT_EQ(uv.x, 0.5f);
  ASSERT_TRUE(IntersectPrim(scene.view, 2, ray, kInfinity, &t, &uv));
  EXPECT_FLOAT_EQ(t, 7.0f);
  EXPECT_FALSE(IntersectPrim(scene.view, 2, ray, 7.0f, &t, &uv));
  // Bounds contain each shape.
  Aabb sb = PrimBounds(scene.sphere);
  EXPECT_TRUE(sb.Contains(vec3(0, 0, -6)) && sb.Contains(vec3(1, 0, -5)));
  Aabb qb = PrimBounds(scene.quad);
  EXPECT_TRUE(qb.Contains(vec3(1, 1, -2)) && qb.Contains(vec3(-1, -1, -2)));
  EXPECT_TRUE(PrimBounds(scene.view, 0).Contains(vec3(0, 1, 0)));
}

TEST(IntersectionAabb, ConservativeAndEmpty) {
  vec3 lo(0.0f), hi(1.0f);
  auto inv = [](vec3 d) { return vec3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z); };
  float tEntry;
  vec3 d(0, 0, -1);
  EXPECT_TRUE(IntersectAabb(lo, hi, vec3(0.5f, 0.5f, 3), inv(d), kInfinity, &tEntry));
  EXPECT_FLOAT_EQ(tEntry, 2.0f);
  EXPECT_FALSE(IntersectAabb(lo, hi, vec3(0.5f, 0.5f, 3), inv(d), 1.5f, &tEntry));
  EXPECT_FALSE(IntersectAabb(lo, hi, vec3(1.5f, 0.5f, 3), inv(d), kInfinity, &tEntry));
  // A ray running inside a face plane (0 * inf = NaN) still counts as touching it.
  EXPECT_TRUE(IntersectAabb(lo, hi, vec3(0.0f, 0.5f, 3), inv(d), kInfinity, &tEntry));
  EXPECT_TRUE(IntersectAabb(lo, hi, vec3(1.0f, 1.0f, 3), inv(d), kInfinity, &tEntry));
  // Inside: entry 0. Flat box hit face-on.
  EXPECT_TRUE(IntersectAabb(lo, hi, vec3(0.5f), inv(d), kInfinity, &tEntry));
  EXPECT_EQ(tEntry, 0.0f);
  EXPECT_TRUE(
      IntersectAabb(vec3(0, 0, 1), vec3(1, 1, 1), vec3(0.3f, 0.3f, 3), inv(d), kInfinity, &tEntry));
  Aabb empty;
  EXPECT_TRUE(empty.IsEmpty());
  for (vec3 dir : {vec3(0, 0, -1), vec3(0, 0, 1), glm::normalize(vec3(1, -2, 3))}) {
    EXPECT_FALSE(IntersectAabb(empty.lo, empty.hi, vec3(0.0f), inv(dir), kInfinity, &tEntry));
  }
}

}  // namespace
}  // namespace pt
