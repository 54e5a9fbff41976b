// Light sampling: Monte Carlo irradiance from quad, triangle, sphere, point and background
// lights against analytic values, LightPdf against the sampled pdf, direction distributions
// against LightPdf (chi-square), light choice against the pmf, and the light table itself.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each). Means use
// tolerance z * sigma / sqrt(n) with z = 3.89 (two-sided 1e-4 under the CLT) and sigma the
// sample standard deviation, plus a stated deterministic allowance for float round-off.
#include <gtest/gtest.h>

#include <random>

#include "src/lights/light_sample.h"
#include "src/lights/light_table.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;
using test::kChiSquareAlpha;  // per-assertion false-alarm probability
constexpr double kRoundOff = 1e-5;  // relative float round-off allowance on irradiance means

using test::Uniform;

// A scene built by hand (no BVH: prims in insertion order) with a real light table.
struct LightScene {
  Scene scene;
  SceneView view;

  uint32_t AddMaterial(vec3 radiance, bool twoSided) {
    Material m;
    m.type = MaterialType::kEmissive;
    m.radiance = radiance;
    m.twoSided = twoSided;
    scene.desc.materials.push_back(m);
    return uint32_t(scene.desc.materials.size() - 1);
  }
  void AddQuad(Quad q, uint32_t mat) {
    scene.desc.quads.push_back(q);
    AddPrim(ShapeType::kQuad, scene.desc.quads.size() - 1, mat);
  }
  void AddTriangle(Triangle t, uint32_t mat) {
    scene.desc.triangles.push_back(t);
    scene.desc.triangleNormals.push_back({});
    AddPrim(ShapeType::kTriangle, scene.desc.triangles.size() - 1, mat);
  }
  void AddSphere(Sphere s, uint32_t mat) {
    scene.desc.spheres.push_back(s);
    AddPrim(ShapeType::kSphere, scene.desc.spheres.size() - 1, mat);
  }
  void AddPrim(ShapeType type, size_t index, uint32_t mat) {
    scene.prims.push_back({PrimRef::Pack(type, uint32_t(index)), mat, -1});
  }
  void Build() {
    BuildLightTable(scene);
    view = HostSceneView(scene);  // no BVH: light sampling never traverses
  }
};

// Irradiance from a uniform Lambertian polygon (Lambert's formula, double precision):
// E = L / 2 * |sum_i angle(g_i, g_i+1) * n . normalize(g_i x g_i+1)|, g_i = unit vectors from x
// to the vertices. Valid when the polygon is wholly above x's horizon.
double PolygonIrradiance(const std::vector<glm::dvec3>& verts, glm::dvec3 x, glm::dvec3 n,
                         double radiance) {
  double sum = 0.0;
  for (size_t i = 0; i < verts.size(); ++i) {
    glm::dvec3 a = glm::normalize(verts[i] - x);
    glm::dvec3 b = glm::normalize(verts[(i + 1) % verts.size()] - x);
    double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * radiance * std::fabs(sum);
}

std::vector<glm::dvec3> QuadVerts(const Quad& q) {
  glm::dvec3 o(q.origin), u(q.u), v(q.v);
  return {o, o + u, o + u + v, o + v};
}

// Mean of sum L.x * max(cos, 0) / pdf over n light samples at x with normal n.
test::MeanEstimate EstimateIrradiance(const SceneView& view, vec3 x, vec3 n, int count,
                                      uint32_t seed, int* pdfMismatches = nullptr) {
  Uniform u(seed);
  test::MeanAccumulator acc;
  for (int i = 0; i < count; ++i) {
    LightLiSample ls;
    double value = 0.0;
    if (SampleLightLi(view, x, u(), u.Get2(), &ls)) {
      value = double(ls.L.x) * std::max(0.0f, glm::dot(ls.wi, n)) / double(ls.pdf);
      // LightPdf must reproduce the pdf of the very sample SampleLightLi drew.
      if (pdfMismatches && !ls.isDelta) {
        float pdf = LightPdf(view, ls.lightIndex, x, ls.pLight, ls.nLight);
        if (!(std::fabs(pdf - ls.pdf) <= 1e-4f * ls.pdf)) ++*pdfMismatches;
      }
    }
    acc.Add(value);
  }
  return acc.Result();
}

// Asserts the irradiance estimate agrees with the analytic value. Statistical part: two-sided
// CLT bound z * sigma / sqrt(n), false-alarm probability 1e-4; plus kRoundOff * expected for
// float round-off (deterministic, it matters only when sigma is ~0, e.g. a distant sphere).
void ExpectIrradiance(const test::MeanEstimate& e, double expected, const char* what) {
  EXPECT_NEAR(e.mean, expected, kZ1e4 * e.stdError + kRoundOff * expected)
      << what << ": standard error " << e.stdError;
}

TEST(LightSampleTest, QuadIrradianceMatchesAnalytic) {
  // A 2a x 2a one-sided square facing down at height h over the origin.
  const float a = 0.5f, h = 0.8f, radiance = 3.0f;
  LightScene ls;
  Quad q{vec3(-a, h, -a), vec3(2 * a, 0, 0), vec3(0, 0, 2 * a)};  // normal (0, -1, 0)
  ls.AddQuad(q, ls.AddMaterial(vec3(radiance), false));
  ls.Build();
  // Closed form for the centred parallel square (four corner rectangles):
  // E = 4 L X / sqrt(1 + X^2) atan(X / sqrt(1 + X^2)), X = a / h. Cross-checks the reference.
  double x = double(a) / h, s = std::sqrt(1 + x * x);
  double closed = 4.0 * radiance * (x / s) * std::atan(x / s);
  double lambert = PolygonIrradiance(QuadVerts(q), {0, 0, 0}, {0, 1, 0}, radiance);
  ASSERT_NEAR(lambert, closed, 1e-12 * closed);

  int mismatches = 0;
  ExpectIrradiance(EstimateIrradiance(ls.view, vec3(0), vec3(0, 1, 0), 200000, 1, &mismatches),
                   closed, "parallel square");
  // Off-centre point with a tilted receiver, light still above its horizon.
  vec3 p(0.3f, -0.2f, 0.1f), n = glm::normalize(vec3(0.2f, 1.0f, -0.3f));
  double expect = PolygonIrradiance(QuadVerts(q), glm::dvec3(p), glm::dvec3(n), radiance);
  ExpectIrradiance(EstimateIrradiance(ls.view, p, n, 200000, 2, &mismatches), expect,
                   "tilted receiver");
  EXPECT_EQ(mismatches, 0);
}

TEST(LightSampleTest, OneSidedQuadIsDarkFromBehindTwoSidedIsNot) {
  const float radiance = 2.0f;
  Quad q{vec3(-0.5f, 1, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1)};  // faces down
  LightScene oneSided, twoSided;
  oneSided.AddQuad(q, oneSided.AddMaterial(vec3(radiance), false));
  twoSided.AddQuad(q, twoSided.AddMaterial(vec3(radiance), true));
  oneSided.Build();
  twoSided.Build();
  vec3 above(0.1f, 1.7f, 0.2f), down(0, -1, 0);
  Uniform u(3);
  for (int i = 0; i < 1000; ++i) {
    LightLiSample s;
    EXPECT_FALSE(SampleLightLi(oneSided.view, above, u(), u.Get2(), &s));
  }
  EXPECT_EQ(LightPdf(oneSided.view, 0, above, vec3(0, 1, 0), vec3(0, -1, 0)), 0.0f);
  double expect = PolygonIrradiance(QuadVerts(q), glm::dvec3(above), glm::dvec3(down), radiance);
  int mismatches = 0;
  ExpectIrradiance(EstimateIrradiance(twoSided.view, above, down, 200000, 4, &mismatches), expect,
                   "two-sided from behind");
  EXPECT_EQ(mismatches, 0);
}

TEST(LightSampleTest, TriangleIrradianceMatchesAnalytic) {
  const float radiance = 5.0f;
  // Counter-clockwise seen from below: normal points down towards the receivers.
  Triangle t{vec3(-0.6f, 1.0f, -0.4f), vec3(0.5f, 1.2f, -0.5f), vec3(0.1f, 0.9f, 0.7f)};
  ASSERT_LT(glm::cross(t.p1 - t.p0, t.p2 - t.p0).y, 0.0f);
  LightScene ls;
  ls.AddTriangle(t, ls.AddMaterial(vec3(radiance), false));
  ls.Build();
  std::vector<glm::dvec3> verts = {glm::dvec3(t.p0), glm::dvec3(t.p1), glm::dvec3(t.p2)};
  int mismatches = 0;
  uint32_t seed = 5;
  for (vec3 p : {vec3(0.0f), vec3(0.4f, 0.3f, -0.6f)}) {
    vec3 n = glm::normalize(vec3(-0.1f, 1.0f, 0.2f));
    double expect = PolygonIrradiance(verts, glm::dvec3(p), glm::dvec3(n), radiance);
    ExpectIrradiance(EstimateIrradiance(ls.view, p, n, 200000, seed++, &mismatches), expect,
                     "triangle");
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(LightSampleTest, SphereIrradianceMatchesAnalytic) {
  // A uniform sphere of radiance L subtending half-angle alpha (sin alpha = r / d) gives
  // E = pi L sin^2(alpha) cos(beta) on a plane tilted by beta, while wholly above its horizon.
  const float radiance = 4.0f;
  int mismatches = 0;
  uint32_t seed = 10;
  for (float d : {1.5f, 10.0f, 3000.0f}) {  // near, far, and tiny (cancellation in 1 - cos)
    for (float beta : {0.0f, 0.3f}) {
      LightScene ls;
      vec3 center(0.2f, 0.1f + d, -0.3f);
      ls.AddSphere({center, 1.0f}, ls.AddMaterial(vec3(radiance), false));
      ls.Build();
      vec3 p(0.2f, 0.1f, -0.3f), n(std::sin(beta), std::cos(beta), 0.0f);
      double expect = M_PI * radiance / (double(d) * d) * std::cos(double(beta));
      ExpectIrradiance(EstimateIrradiance(ls.view, p, n, 100000, seed++, &mismatches), expect,
                       "sphere");
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(LightSampleTest, InsideSphereLightIsUniformWhenTwoSided) {
  // Inside a two-sided emitting sphere every direction sees radiance L: E = pi L on any plane.
  // A one-sided sphere emits outwards only, so inside it is dark.
  const float radiance = 1.5f;
  Sphere sp{vec3(1, 2, 3), 2.0f};
  LightScene twoSided, oneSided;
  twoSided.AddSphere(sp, twoSided.AddMaterial(vec3(radiance), true));
  oneSided.AddSphere(sp, oneSided.AddMaterial(vec3(radiance), false));
  twoSided.Build();
  oneSided.Build();
  vec3 p = sp.center + vec3(0.5f, -1.2f, 0.3f), n = glm::normalize(vec3(1, 1, 1));
  int mismatches = 0;
  ExpectIrradiance(EstimateIrradiance(twoSided.view, p, n, 200000, 20, &mismatches),
                   M_PI * radiance, "inside two-sided sphere");
  EXPECT_EQ(mismatches, 0);
  Uniform u(21);
  for (int i = 0; i < 1000; ++i) {
    LightLiSample s;
    EXPECT_FALSE(SampleLightLi(oneSided.view, p, u(), u.Get2(), &s));
  }
}

TEST(LightSampleTest, PointAndBackgroundLights) {
  LightScene ls;
  ls.scene.desc.pointLights.push_back({vec3(0, 2, 0), vec3(8.0f)});
  ls.scene.desc.background = vec3(0.5f);
  ls.scene.sceneRadius = 3.0f;
  ls.Build();
  ASSERT_EQ(ls.view.lightCount, 2u);
  ASSERT_EQ(ls.view.backgroundLight, 1);
  // Point: deterministic intensity / d^2 with pdf = its choice probability.
  vec3 x(0, 0, 0);
  LightLiSample s;
  ASSERT_TRUE(SampleLightLi(ls.view, x, 0.0f, vec2(0.5f), &s));
  EXPECT_TRUE(s.isDelta);
  EXPECT_EQ(s.lightIndex, 0);
  EXPECT_FLOAT_EQ(s.L.x, 8.0f / 4.0f);
  EXPECT_EQ(s.pdf, ls.view.lightPmf[0]);
  EXPECT_EQ(s.wi, vec3(0, 1, 0));
  EXPECT_EQ(LightPdf(ls.view, 0, x, s.pLight, s.nLight), 0.0f);  // a point cannot be hit
  // Background: a uniform environment gives E = pi L_bg, plus the point light's I / d^2.
  double expect = M_PI * 0.5 + 8.0 / 4.0;
  Uniform u(30);
  test::MeanAccumulator acc;
  for (int i = 0; i < 200000; ++i) {
    double value = 0.0;
    if (SampleLightLi(ls.view, x, u(), u.Get2(), &s)) {
      value = double(s.L.x) * std::max(0.0f, s.wi.y) / double(s.pdf);
      if (s.isInfinite) {
        EXPECT_EQ(s.pdf, BackgroundLightPdf(ls.view));
        EXPECT_EQ(LightPdf(ls.view, s.lightIndex, x, s.pLight, s.nLight), s.pdf);
      }
    }
    acc.Add(value);
  }
  // CLT bound, two-sided false-alarm probability 1e-4, plus round-off allowance.
  ExpectIrradiance(acc.Result(), expect, "point + background");
}

// ---- A scene with every kind of light ----

// Quad (one-sided, facing down), triangle (two-sided), sphere, point light, background, and a
// non-emitting quad. Area lights are in shape order (triangles, quads, spheres: tagIndex), so
// the light order is triangle 0, quad 1, sphere 2, point 3, background 4, while the primitive
// order is floor 0, quad 1, triangle 2, sphere 3.
void BuildMixedScene(LightScene* ls) {
  Material white;
  white.albedo = vec3(0.5f);
  ls->scene.desc.materials.push_back(white);
  ls->AddQuad({vec3(-1, -1, -1), vec3(2, 0, 0), vec3(0, 0, 2)}, 0);  // a floor, not a light
  ls->AddQuad({vec3(-0.4f, 2, -0.3f), vec3(0.8f, 0, 0), vec3(0, 0, 0.6f)},
              ls->AddMaterial(vec3(6, 5, 4), false));
  ls->AddTriangle({vec3(-1.5f, 1, 0), vec3(-1, 1.5f, 0.5f), vec3(-1.2f, 1.8f, -0.5f)},
                  ls->AddMaterial(vec3(2, 3, 4), true));
  ls->AddSphere({vec3(1.5f, 1, 0), 0.3f}, ls->AddMaterial(vec3(10, 10, 10), false));
  ls->scene.desc.pointLights.push_back({vec3(0.3f, 1.5f, 0.8f), vec3(1.0f)});
  ls->scene.desc.background = vec3(0.2f, 0.3f, 0.4f);
  ls->scene.sceneCenter = vec3(0, 0.5f, 0);
  ls->scene.sceneRadius = 2.5f;
  ls->Build();
}

TEST(LightTableTest, LightsAndPowerProportionalPmf) {
  LightScene ls;
  BuildMixedScene(&ls);
  const Scene& sc = ls.scene;
  ASSERT_EQ(sc.lights.size(), 5u);
  EXPECT_EQ(sc.prims[0].light, -1);
  const int lightOfPrim[4] = {-1, 1, 0, 2};
  for (int i = 1; i <= 3; ++i) {
    EXPECT_EQ(sc.prims[i].light, lightOfPrim[i]);
    EXPECT_EQ(sc.lights[lightOfPrim[i]].type, LightType::kArea);
    EXPECT_EQ(sc.lights[lightOfPrim[i]].prim, uint32_t(i));
  }
  EXPECT_EQ(sc.lights[3].type, LightType::kPoint);
  EXPECT_EQ(sc.lights[4].type, LightType::kBackground);
  EXPECT_EQ(sc.backgroundLight, 4);
  double pi = M_PI, r = 2.5;
  double power[5] = {Luminance(vec3(2, 3, 4)) * double(TriangleArea(sc.desc.triangles[0])) * pi * 2,
                     Luminance(vec3(6, 5, 4)) * 0.48 * pi,
                     Luminance(vec3(10.0f)) * 4 * pi * 0.09 * pi, 4 * pi * Luminance(vec3(1.0f)),
                     Luminance(vec3(0.2f, 0.3f, 0.4f)) * 4 * pi * pi * r * r};
  double total = 0;
  for (double p : power) total += p;
  ASSERT_EQ(sc.lightCdf.size(), 6u);
  EXPECT_EQ(sc.lightCdf[0], 0.0f);
  EXPECT_EQ(sc.lightCdf[5], 1.0f);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(sc.lightPmf[i], power[i] / total, 1e-6) << "light " << i;
    EXPECT_EQ(sc.lightPmf[i], sc.lightCdf[i + 1] - sc.lightCdf[i]);
  }
}

TEST(LightTableTest, ZeroPowerAndNoLights) {
  // Black point lights carry no power: they are dropped from the table (issue 30: emitters with
  // zero power are never sampled), so the scene has nothing to sample, like one with no lights.
  LightScene dark;
  dark.scene.desc.pointLights = {{vec3(0), vec3(0)}, {vec3(1), vec3(0)}};
  dark.AddSphere({vec3(0), 1}, dark.AddMaterial(vec3(0), false));  // black: not a light
  dark.Build();
  EXPECT_EQ(dark.view.lightCount, 0u);
  EXPECT_EQ(dark.scene.prims[0].light, -1);
  EXPECT_EQ(dark.view.backgroundLight, -1);
  EXPECT_EQ(BackgroundLightPdf(dark.view), 0.0f);
  LightLiSample s;
  EXPECT_FALSE(SampleLightLi(dark.view, vec3(0.5f), 0.5f, vec2(0.5f), &s));
  LightScene none;
  none.Build();
  EXPECT_EQ(none.view.lightCount, 0u);
  EXPECT_FALSE(SampleLightLi(none.view, vec3(0), 0.5f, vec2(0.5f), &s));
}

TEST(LightSampleTest, LightChoiceFollowsPmf) {
  LightScene ls;
  BuildMixedScene(&ls);
  const int64_t n = 200000;
  std::vector<double> observed(5, 0.0), expected(5);
  Uniform u(40);
  for (int64_t i = 0; i < n; ++i) observed[SampleLightIndex(ls.view, u())] += 1;
  for (int i = 0; i < 5; ++i) expected[i] = n * double(ls.view.lightPmf[i]);
  test::ChiSquareResult r = test::PearsonChiSquare(observed, expected, double(n), 5.0);
  // Chi-square goodness of fit of the multinomial counts: false-alarm probability 1e-4.
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;
}

TEST(LightSampleTest, MixedSceneIrradianceAndLightPdf) {
  LightScene ls;
  BuildMixedScene(&ls);
  const SceneDesc& d = ls.scene.desc;
  vec3 x(0.1f, 0.0f, -0.2f), n(0, 1, 0);
  // Red channel of each light's unoccluded irradiance at x.
  glm::dvec3 xd(x), nd(n);
  double e = PolygonIrradiance(QuadVerts(d.quads[1]), xd, nd, 6.0);
  const Triangle& t = d.triangles[0];
  e += PolygonIrradiance({glm::dvec3(t.p0), glm::dvec3(t.p1), glm::dvec3(t.p2)}, xd, nd, 2.0);
  glm::dvec3 toSphere = glm::dvec3(d.spheres[0].center) - xd;
  double dist2 = glm::dot(toSphere, toSphere);
  e += M_PI * 10.0 * 0.09 / dist2 * toSphere.y / std::sqrt(dist2);
  glm::dvec3 toPoint = glm::dvec3(d.pointLights[0].position) - xd;
  double pd2 = glm::dot(toPoint, toPoint);
  e += 1.0 * toPoint.y / std::sqrt(pd2) / pd2;
  e += M_PI * 0.2;
  int mismatches = 0;
  // CLT bound (false-alarm probability 1e-4) plus round-off allowance, in ExpectIrradiance.
  ExpectIrradiance(EstimateIrradiance(ls.view, x, n, 400000, 41, &mismatches), e, "mixed");
  EXPECT_EQ(mismatches, 0);
}

// Directions from SampleLightLi are distributed as the sum over lights of LightPdf at every
// light surface the direction meets (sampling ignores occlusion). Point-light samples are
// counted as failures: their mass is the pdf's shortfall from 1.
double MixedDirectionPdf(const SceneView& v, vec3 x, vec3 w) {
  double pdf = BackgroundLightPdf(v);
  const Quad& q = v.quads[1];
  vec3 qn = glm::cross(q.u, q.v);
  float tq = glm::dot(q.origin - x, qn) / glm::dot(w, qn);
  vec3 dq = x + tq * w - q.origin;
  float s = glm::dot(glm::cross(dq, q.v), qn) / glm::dot(qn, qn);
  float r = glm::dot(glm::cross(q.u, dq), qn) / glm::dot(qn, qn);
  if (tq > 0 && s >= 0 && s <= 1 && r >= 0 && r <= 1)
    pdf += LightPdf(v, v.prims[1].light, x, x + tq * w, glm::normalize(qn));
  const Triangle& t = v.triangles[0];  // Moller-Trumbore
  vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, pv = glm::cross(w, e2);
  float det = glm::dot(e1, pv), inv = 1.0f / det;
  vec3 tv = x - t.p0, qv = glm::cross(tv, e1);
  float b1 = glm::dot(tv, pv) * inv, b2 = glm::dot(w, qv) * inv, tt = glm::dot(e2, qv) * inv;
  if (det != 0 && b1 >= 0 && b2 >= 0 && b1 + b2 <= 1 && tt > 0)
    pdf += LightPdf(v, v.prims[2].light, x, x + tt * w, glm::normalize(glm::cross(e1, e2)));
  const Sphere& sp = v.spheres[0];
  vec3 oc = x - sp.center;
  float b = glm::dot(oc, w), c = glm::dot(oc, oc) - sp.radius * sp.radius, disc = b * b - c;
  if (disc >= 0 && -b - std::sqrt(disc) > 0) {
    vec3 p = x + (-b - std::sqrt(disc)) * w;
    pdf += LightPdf(v, v.prims[3].light, x, p, (p - sp.center) / sp.radius);
  }
  return pdf;
}

TEST(LightSampleTest, MixedSceneDirectionsFollowLightPdf) {
  LightScene ls;
  BuildMixedScene(&ls);
  Uniform u(42);
  for (vec3 x : {vec3(0.1f, 0.0f, -0.2f), vec3(1.2f, 1.4f, 0.3f)}) {
    auto sample = [&](vec3* w) {
      LightLiSample s;
      if (!SampleLightLi(ls.view, x, u(), u.Get2(), &s) || s.isDelta) return false;
      *w = s.wi;
      return true;
    };
    auto pdf = [&](vec3 w) { return MixedDirectionPdf(ls.view, x, w); };
    test::ChiSquareOptions o;
    o.refine = 128;  // light outlines cut bins: integrate those finely (error ~1/128)
    test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 200000, o);
    // Chi-square goodness of fit: false-alarm probability kChiSquareAlpha = 1e-4 per point.
    EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;
  }
}

}  // namespace
}  // namespace pt
