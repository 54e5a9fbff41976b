// The environment map and distant lights as lights, below the renderer: the map's direction
// convention, its sampling tables against the map, chi-square tests of the sampled directions
// against the pdf that MIS evaluates (a smooth map, a map with one tiny hot texel, a rotated
// map, uniform sampling), zero texels never sampled, irradiance of a constant map and of sun
// disks against their analytic values.
//
// Every statistical assertion has false-alarm probability <= 1e-4 (stated at each); seeds are
// fixed, so a run is reproducible.
#include <gtest/gtest.h>

#include <cmath>

#include "src/lights/environment.h"
#include "src/lights/light_sample.h"
#include "src/lights/light_table.h"
#include "tests/stat_test_util.h"

namespace pt {
namespace {

using test::kZ1e4;
using test::Uniform;
using test::kChiSquareAlpha;  // per-assertion false-alarm probability

// A scene with only an environment map (and optionally directional lights), its light table
// and view built as BuildScene would.
struct MapScene {
  Scene scene;
  SceneView view;

  MapScene(uint32_t width, std::vector<vec3> texels, vec3 rotate = vec3(0.0f)) {
    EnvironmentDesc& e = scene.desc.environment;
    e.width = width;
    e.height = width / 2;
    e.texels = std::move(texels);
    e.rotateDegrees = rotate;
    scene.sceneRadius = 1.0f;
  }
  explicit MapScene(std::vector<DirectionalLightDesc> lights) {
    scene.desc.directionalLights = std::move(lights);
    scene.sceneRadius = 1.0f;
  }
  void Build(bool uniform = false) {
    BuildLightTable(scene);
    view = HostSceneView(scene);
    view.env.uniformSampling = uniform ? 1u : 0u;
  }
};

// The map convention in double: texel (i, j) centre direction.
glm::dvec3 TexelCentre(uint32_t i, uint32_t j, uint32_t w, uint32_t h) {
  double theta = M_PI * (j + 0.5) / h, phi = 2.0 * M_PI * ((i + 0.5) / w - 0.5);
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

double TexelSolidAngle(uint32_t j, uint32_t w, uint32_t h) {
  return (std::cos(M_PI * j / h) - std::cos(M_PI * (j + 1) / h)) * 2.0 * M_PI / w;
}

std::vector<vec3> SmoothMap(uint32_t w) {
  uint32_t h = w / 2;
  std::vector<vec3> t(size_t(w) * h);
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) {
      glm::dvec3 d = TexelCentre(i, j, w, h);
      t[size_t(j) * w + i] = vec3(float(1.2 + d.x), float(0.5 + 0.4 * d.y * d.y), float(1.0 + d.z));
    }
  return t;
}

TEST(EnvMapTest, ConventionCentreColumnFacesMinusZTopRowPlusY) {
  const uint32_t w = 16, h = 8;
  MapScene m(w, std::vector<vec3>(w * h, vec3(1.0f)));
  m.Build();
  const EnvironmentView& e = m.view.env;
  // Just inside the texels on either side of the stated directions.
  auto texel = [&](vec3 d) { return EnvTexelOf(e, glm::normalize(d)); };
  EXPECT_EQ(texel(vec3(0.01f, 0.01f, -1)).i, w / 2);      // -Z: centre column, u just past 0.5
  EXPECT_EQ(texel(vec3(-0.01f, 0.01f, -1)).i, w / 2 - 1);  // towards -X: u below 0.5
  EXPECT_EQ(texel(vec3(1, 0.01f, 0.01f)).i, 3 * w / 4);    // +X: u = 0.75
  EXPECT_EQ(texel(vec3(-1, 0.01f, -0.01f)).i, w / 4);      // -X: u = 0.25
  EXPECT_EQ(texel(vec3(0.01f, 1, 0)).j, 0u);               // +Y: top row
  EXPECT_EQ(texel(vec3(0.01f, -1, 0)).j, h - 1);           // -Y: bottom row
  EXPECT_EQ(texel(vec3(0, 0.01f, -1)).j, h / 2 - 1);       // just above the horizon
  // The sampler's mapping: the middle of each texel (in solid angle: cos(theta) halfway
  // across the row) is that texel again, and the direction the convention states.
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) {
      vec3 d = EnvTexelDirection(e, {i, j}, 0.5f, 0.5f);
      EnvTexel back = EnvTexelOf(e, d);
      EXPECT_EQ(back.i, i);
      EXPECT_EQ(back.j, j);
      double z = 0.5 * (std::cos(M_PI * j / h) + std::cos(M_PI * (j + 1) / h));
      double r = std::sqrt(1.0 - z * z), phi = 2.0 * M_PI * ((i + 0.5) / w - 0.5);
      glm::dvec3 expected(r * std::sin(phi), z, -r * std::cos(phi));
      EXPECT_LT(glm::length(glm::dvec3(d) - expected), 1e-6) << i << ", " << j;
    }
}

TEST(EnvMapTest, RotateTurnsTheMapAsObjectTransformsTurn) {
  const uint32_t w = 16, h = 8;
  MapScene m(w, std::vector<vec3>(w * h, vec3(1.0f)), vec3(0, 90, 0));
  m.Build();
  // Ry(90) takes the map's -Z (its centre column) to world -X.
  EnvTexel t = EnvTexelOf(m.view.env, glm::normalize(vec3(-1, 0.01f, -0.01f)));
  EXPECT_EQ(t.i, w / 2);
  vec3 centre = EnvTexelDirection(m.view.env, {w / 2, h / 2 - 1}, 0.0f, 1.0f);
  EXPECT_NEAR(centre.x, -1.0f, 1e-6f);
}

TEST(EnvMapTest, TablesAreLuminanceTimesSolidAngle) {
  const uint32_t w = 32, h = 16;
  std::vector<vec3> map = SmoothMap(w);
  map[5 * w + 7] = vec3(0.0f);  // a black texel has probability exactly 0
  MapScene m(w, map);
  m.Build();
  double total = 0.0;
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) total += Luminance(map[j * w + i]) * TexelSolidAngle(j, w, h);
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) {
      double expected = Luminance(map[j * w + i]) * TexelSolidAngle(j, w, h) / total;
      double pdf = EnvTexelPdf(m.view, {i, j});
      // The pdf times the texel's solid angle is its probability (float tables: 1e-5).
      EXPECT_NEAR(pdf * TexelSolidAngle(j, w, h), expected, 1e-5 * expected + 1e-9)
          << i << ", " << j;
      // and it is proportional to the luminance that is evaluated.
      EXPECT_NEAR(pdf * total, Luminance(map[j * w + i]), 1e-5 * Luminance(map[j * w + i]));
    }
  EXPECT_EQ(EnvTexelPdf(m.view, {7, 5}), 0.0f);
}

// Pearson's chi-square of sampled directions binned by texel (binned in double, not by the
// renderer's lookup), against the pdf the renderer evaluates (EnvMapPdf at the texel's
// centre) times the texel's exact solid angle: the pdf is constant over a texel, so this is
// the exact expected mass, even for a texel a thousand times brighter than its neighbours.
test::ChiSquareResult TexelChiSquare(const MapScene& m, int64_t n, uint32_t seed) {
  uint32_t w = m.view.env.width, h = m.view.env.height;
  glm::dmat3 toLocal(m.view.env.toLocal);
  std::vector<double> observed(size_t(w) * h + 1, 0.0), expected(size_t(w) * h + 1, 0.0);
  Uniform u(seed);
  for (int64_t k = 0; k < n; ++k) {
    vec3 wi, L;
    float pdf;
    if (!SampleEnvMap(m.view, u.Get2(), &wi, &L, &pdf)) {
      observed.back() += 1;
      continue;
    }
    glm::dvec3 d = toLocal * glm::dvec3(wi);
    double theta = std::atan2(std::hypot(d.x, d.z), d.y);
    double uu = 0.5 + std::atan2(d.x, -d.z) / (2.0 * M_PI);
    uint32_t j = std::min(h - 1, uint32_t(theta / M_PI * h));
    uint32_t i = std::min(w - 1, uint32_t(uu * w));
    observed[size_t(j) * w + i] += 1;
  }
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) {
      vec3 centre = glm::normalize(m.view.env.toWorld * vec3(TexelCentre(i, j, w, h)));
      expected[size_t(j) * w + i] = EnvMapPdf(m.view, centre) * TexelSolidAngle(j, w, h) * n;
    }
  return test::PearsonChiSquare(observed, expected, double(n), 5.0);
}

TEST(EnvMapTest, SampledDirectionsFollowTheEvaluatedPdf) {
  const uint32_t w = 32;
  MapScene smooth(w, SmoothMap(w), vec3(20, -35, 10));
  smooth.Build();
  // Chi-square per texel: false-alarm probability 1e-4.
  test::ChiSquareResult r = TexelChiSquare(smooth, 400000, 1);
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;
  // And over bins that cut across texels, by the shared chi-square helper (Simpson's rule of
  // the pdf, finer where it jumps): the rotated map's pdf as a density on the sphere.
  Uniform u(2);
  auto sample = [&](vec3* d) {
    vec3 L;
    float pdf;
    return SampleEnvMap(smooth.view, u.Get2(), d, &L, &pdf);
  };
  auto pdf = [&](vec3 d) { return double(EnvMapPdf(smooth.view, d)); };
  test::ChiSquareOptions o;
  o.thetaBins = 10;
  o.phiBins = 20;
  o.refine = 64;
  r = test::ChiSquareDirections(sample, pdf, 400000, o);
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;  // false-alarm probability 1e-4
}

TEST(EnvMapTest, TinyHotSpotIsSampledInProportion) {
  const uint32_t w = 64, h = 32;
  std::vector<vec3> map(w * h, vec3(0.05f));
  map[11 * w + 40] = vec3(2000.0f, 1500.0f, 1000.0f);  // a sun: one texel, most of the power
  MapScene m(w, map);
  m.Build();
  test::ChiSquareResult r = TexelChiSquare(m, 400000, 3);
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;  // false-alarm probability 1e-4
}

TEST(EnvMapTest, OneBrightTexelIsAllThatIsSampledAndItsDirectionIsKnown) {
  const uint32_t w = 32, h = 16;
  std::vector<vec3> map(w * h, vec3(0.0f));
  // Column 3w/4 (u = 0.75: +X), the row just above the horizon.
  uint32_t bi = 3 * w / 4, bj = h / 2 - 1;
  map[bj * w + bi] = vec3(5.0f);
  MapScene m(w, map);
  m.Build();
  ASSERT_EQ(m.view.lightCount, 1u);
  Uniform u(4);
  double cosMax = std::cos(1.5 * 2.0 * M_PI / w);  // within a texel's diagonal of +X
  for (int k = 0; k < 20000; ++k) {
    LightLiSample s;
    ASSERT_TRUE(SampleLightLi(m.view, vec3(0), u(), u.Get2(), &s));
    EXPECT_EQ(s.L, vec3(5.0f));
    EXPECT_GT(s.wi.x, cosMax);
    EXPECT_GE(s.wi.y, 0.0f);
    EnvTexel t = EnvTexelOf(m.view.env, s.wi);
    EXPECT_TRUE(t.i == bi && t.j == bj) << t.i << ", " << t.j;
    // The pdf MIS evaluates for this direction is the sample's.
    float lightPdf;
    EXPECT_EQ(EnvMapLightLe<true>(m.view, s.wi, &lightPdf), vec3(5.0f));
    EXPECT_FLOAT_EQ(lightPdf, s.pdf);
  }
  // Any direction outside the texel has pdf 0: it is never sampled.
  EXPECT_EQ(EnvMapPdf(m.view, vec3(-1, 0, 0)), 0.0f);
  EXPECT_EQ(EnvMapPdf(m.view, vec3(0, 1, 0)), 0.0f);
}

TEST(EnvMapTest, UniformSamplingIsUniform) {
  const uint32_t w = 16;
  MapScene m(w, SmoothMap(w));
  m.Build(/*uniform=*/true);
  Uniform u(5);
  auto sample = [&](vec3* d) {
    vec3 L;
    float pdf;
    return SampleEnvMap(m.view, u.Get2(), d, &L, &pdf) && pdf == UniformSpherePdf();
  };
  auto pdf = [&](vec3 d) { return double(EnvMapPdf(m.view, d)); };
  test::ChiSquareResult r = test::ChiSquareDirections(sample, pdf, 200000);
  EXPECT_GT(r.pValue, kChiSquareAlpha) << r.message;  // false-alarm probability 1e-4
}

// Mean over n light samples of L.x max(cos, 0) / pdf at the origin, normal nrm.
test::MeanEstimate Irradiance(const SceneView& v, vec3 nrm, int n, uint32_t seed) {
  Uniform u(seed);
  test::MeanAccumulator acc;
  for (int k = 0; k < n; ++k) {
    LightLiSample s;
    double value = 0.0;
    if (SampleLightLi(v, vec3(0), u(), u.Get2(), &s))
      value = double(s.L.x) * std::max(0.0f, glm::dot(s.wi, nrm)) / double(s.pdf);
    acc.Add(value);
  }
  return acc.Result();
}

TEST(EnvMapTest, ConstantMapGivesPiLOnEveryPlane) {
  const uint32_t w = 64;
  for (bool uniform : {false, true}) {
    MapScene m(w, std::vector<vec3>(w * w / 2, vec3(0.7f)));
    m.scene.desc.environment.strength = 2.0f;
    m.Build(uniform);
    for (vec3 nrm : {vec3(0, 1, 0), glm::normalize(vec3(1, -2, 0.5f))}) {
      test::MeanEstimate e = Irradiance(m.view, nrm, 100000, 6);
      // CLT bound, two-sided false-alarm probability 1e-4, plus float round-off.
      EXPECT_NEAR(e.mean, M_PI * 1.4, kZ1e4 * e.stdError + 1e-5) << "uniform " << uniform;
    }
  }
}

TEST(DirectionalLightTest, SunDiskIrradianceIsItsStatedValueTimesCosine) {
  const double kDeg = M_PI / 180.0;
  vec3 toSun = glm::normalize(vec3(0.3f, 1.0f, -0.2f));
  for (double radius : {0.0, 0.2666 * kDeg, 5.0 * kDeg}) {
    DirectionalLightDesc d;
    d.direction = toSun;
    d.irradiance = vec3(3.0f, 2.0f, 1.0f);
    d.angularRadius = float(radius);
    MapScene m({d});
    m.Build();
    ASSERT_EQ(m.view.distantLightCount, radius > 0.0 ? 1u : 0u);
    for (vec3 nrm : {toSun, vec3(0, 1, 0), glm::normalize(vec3(1, 0.5f, 0))}) {
      test::MeanEstimate e = Irradiance(m.view, nrm, 20000, 7);
      double expected = 3.0 * glm::dot(glm::dvec3(toSun), glm::dvec3(nrm));
      // The cone lies wholly above each plane, where E = E_sun cos(beta) exactly; CLT bound
      // (false-alarm probability 1e-4) plus float round-off.
      EXPECT_NEAR(e.mean, expected, kZ1e4 * e.stdError + 1e-5 * expected) << radius;
    }
    // Every sample lies in the cone, and the pdf MIS evaluates for it is the sample's.
    Uniform u(8);
    for (int k = 0; k < 2000 && radius > 0.0; ++k) {
      LightLiSample s;
      ASSERT_TRUE(SampleLightLi(m.view, vec3(0), u(), u.Get2(), &s));
      EXPECT_FALSE(s.isDelta);
      EXPECT_TRUE(InDirectionalCone(m.view.lights[0], s.wi));
      EXPECT_FLOAT_EQ(LightPdf(m.view, 0, vec3(0), s.pLight, s.nLight), s.pdf);
      EXPECT_GE(double(glm::dot(s.wi, toSun)), std::cos(radius) - 1e-6);
    }
  }
}

}  // namespace
}  // namespace pt
