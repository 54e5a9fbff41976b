// The light BVH (src/lights/light_bvh.h): on small trees of mixed lights, every light's
// probability from LightTreePmf equals the product an independent enumeration of the tree
// gives, the probabilities sum to the mass the walk can reach (1 where no node is a dead end),
// the lights SampleLightTree chooses follow those probabilities (chi-square), each returned
// pmf is bit for bit LightTreePmf's, a leaf's importance is never 0 where its light reaches
// the receiver, and next-event estimation through the tree gives the analytic irradiance.
//
// Statistical assertions have false-alarm probability 1e-4 each (kZ1e4, kChiSquareAlpha).
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "src/lights/light_bvh_build.h"
#include "src/lights/light_sample.h"
#include "src/lights/light_table.h"
#include "tests/light_bvh_test_util.h"
#include "tests/stat_test_util.h"

namespace pt::test {
namespace {

// Probability of each light by walking every branch of the tree, in double.
void Enumerate(const SceneView& v, const LightRef& r, uint32_t node, double p,
               std::map<uint32_t, double>* out, double* mass) {
  const LightBvhNode& n = v.lightNodes[node];
  if (n.IsLeaf()) {
    // A single light (the root a leaf) is chosen wherever the point is.
    (*out)[n.Light()] += p;
    *mass += p;
    return;
  }
  double c0 = NodeImportance(v, n.child, r), c1 = NodeImportance(v, n.child + 1, r);
  if (!(c0 + c1 > 0.0)) return;
  Enumerate(v, r, n.child, p * c0 / (c0 + c1), out, mass);
  Enumerate(v, r, n.child + 1, p * c1 / (c0 + c1), out, mass);
}

// Reference points with no normal, a one-sided normal and a two-sided one.
std::vector<LightRef> RandomRefs(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  std::vector<LightRef> refs;
  for (int i = 0; i < count; ++i) {
    LightRef r;
    r.p = vec3(u(rng), u(rng), u(rng));
    if (i % 3 != 0) r.n = RandomUnit(rng);
    r.twoSided = i % 3 == 2;
    // Through the packing the renderer uses, so the normal is exactly representable.
    if (i % 3 != 0) r = ReceiverRef(r.p, PackReceiver(r.n, r.twoSided));
    refs.push_back(r);
  }
  return refs;
}

TEST(LightBvh, EveryLightsPmfIsTheProductAlongItsPath) {
  for (int n : {1, 2, 3, 5, 17, 64, 300}) {
    LightTestScene ls = RandomLights(n, 10 + n);
    ASSERT_EQ(ls.scene.lightTree.boundedCount, uint32_t(n));
    // One light per leaf, plus node 1 (padding: siblings start at even indices).
    ASSERT_EQ(ls.scene.lightTree.nodeCount, uint32_t(2 * n)) << "one light per leaf";
    for (const LightRef& r : RandomRefs(30, n)) {
      std::map<uint32_t, double> expected;
      double mass = 0.0;
      Enumerate(ls.view, r, 0, 1.0, &expected, &mass);
      double sum = 0.0;
      for (uint32_t i = 0; i < uint32_t(n); ++i) {
        double pmf = LightTreePmf(ls.view, r, i);
        double want = expected.count(i) ? expected[i] : 0.0;
        EXPECT_NEAR(pmf, want, 1e-5 * want + 1e-12) << n << " lights, light " << i;
        sum += pmf;
      }
      EXPECT_NEAR(sum, mass, 1e-5) << n << " lights";
    }
  }
}

// Lights that shine every way (spheres, point lights) seen from points with no receiver
// normal: no importance is 0, no node a dead end, and the probabilities sum to 1.
TEST(LightBvh, OmnidirectionalLightsSumToOne) {
  LightTestScene ls;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f), u01(0.0f, 1.0f);
  for (int i = 0; i < 90; ++i) {
    vec3 c(u(rng), u(rng), u(rng)), power(std::pow(10.0f, 3.0f * u01(rng) - 1.5f));
    if (i % 3 == 0) ls.AddSphere(Sphere{c, 0.1f * u01(rng) + 0.01f}, ls.AddEmissive(power, false));
    else ls.scene.desc.pointLights.push_back(PointLightDesc{c, power});
  }
  ls.Build(LightSampler::kBvh);
  for (const LightRef& r : RandomRefs(40, 3)) {
    if (r.n != vec3(0.0f)) continue;
    double sum = 0.0;
    for (uint32_t i = 0; i < ls.view.lightCount; ++i) sum += LightTreePmf(ls.view, r, i);
    EXPECT_NEAR(sum, 1.0, 1e-5);
  }
}

TEST(LightBvh, ChoicesOverAllLightsSumToOneForEverySampler) {
  LightTestScene ls = RandomLights(40, 3, /*infinite=*/true);
  ASSERT_GT(ls.scene.lights.size(), 40u);  // plus background and a sun disk
  for (LightSampler s : {LightSampler::kUniform, LightSampler::kPower, LightSampler::kBvh}) {
    ls.view.lightTree.sampler = uint32_t(s);
    for (const LightRef& r : RandomRefs(12, 5)) {
      double sum = 0.0;
      for (uint32_t i = 0; i < ls.view.lightCount; ++i) sum += LightChoicePmf(ls.view, r, i);
      double reach = 1.0;
      if (s == LightSampler::kBvh) {  // the tree's share times what its walk can reach
        std::map<uint32_t, double> unused;
        double mass = 0.0;
        Enumerate(ls.view, r, 0, 1.0, &unused, &mass);
        reach = 1.0 - LightTreeShare(ls.view) * (1.0 - mass);
      }
      EXPECT_NEAR(sum, reach, 1e-5) << LightSamplerName(s);
    }
  }
}

TEST(LightBvh, ChosenLightsFollowThePmfAndReportIt) {
  LightTestScene ls = RandomLights(24, 77, /*infinite=*/true);
  ls.view.lightTree.sampler = uint32_t(LightSampler::kBvh);
  const int kDraws = 200000;
  for (const LightRef& r : RandomRefs(4, 9)) {
    Uniform u(31);
    std::vector<double> observed(ls.view.lightCount, 0.0), expected(ls.view.lightCount, 0.0);
    int mismatches = 0;
    for (int k = 0; k < kDraws; ++k) {
      float pmf = 0.0f;
      int i = ChooseLight(ls.view, r, u(), u(), &pmf);
      if (i < 0) continue;
      observed[i] += 1.0;
      if (pmf != LightChoicePmf(ls.view, r, uint32_t(i))) ++mismatches;
    }
    for (uint32_t i = 0; i < ls.view.lightCount; ++i)
      expected[i] = kDraws * double(LightChoicePmf(ls.view, r, i));
    ChiSquareResult chi = PearsonChiSquare(observed, expected, kDraws, 5.0);
    EXPECT_GT(chi.pValue, kChiSquareAlpha) << chi.message;
    EXPECT_EQ(mismatches, 0);
  }
}

// A deep tree: 4000 point lights whose intensities span 6 decades, so some paths have
// probabilities far below 2^-12 and the walk switches to its second random number.
TEST(LightBvh, DeepTreesKeepTheirFrequencies) {
  LightTestScene ls;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < 4000; ++i) {
    float x = 40.0f * u01(rng) - 20.0f, z = 40.0f * u01(rng) - 20.0f;
    ls.scene.desc.pointLights.push_back(
        PointLightDesc{vec3(x, 1.0f, z), vec3(std::pow(10.0f, 6.0f * u01(rng) - 3.0f))});
  }
  ls.Build(LightSampler::kBvh);
  LightRef r;
  r.p = vec3(0.5f, 0.0f, 0.5f);
  r.n = vec3(0, 1, 0);
  r.twoSided = false;
  // Group lights into 20 bins of equal expected mass, to keep every bin's count large.
  std::vector<std::pair<double, uint32_t>> pmfs;
  for (uint32_t i = 0; i < ls.view.lightCount; ++i)
    pmfs.push_back({LightChoicePmf(ls.view, r, i), i});
  std::sort(pmfs.begin(), pmfs.end());
  std::vector<int> bin(ls.view.lightCount);
  double cumulative = 0.0;
  for (auto [p, i] : pmfs) {
    bin[i] = std::min(19, int(cumulative * 20.0));
    cumulative += p;
  }
  const int kDraws = 400000;
  std::vector<double> observed(20, 0.0), expected(20, 0.0);
  for (auto [p, i] : pmfs) expected[bin[i]] += kDraws * p;
  Uniform u(8);
  for (int k = 0; k < kDraws; ++k) {
    float pmf;
    int i = ChooseLight(ls.view, r, u(), u(), &pmf);
    if (i >= 0) observed[bin[i]] += 1.0;
  }
  ChiSquareResult chi = PearsonChiSquare(observed, expected, kDraws, 5.0);
  EXPECT_GT(chi.pValue, kChiSquareAlpha) << chi.message;
}

// The exact culls: a flat node gives 0 to a point just behind its lights, which the cone
// bound alone does not, yet never to a point in front of them, even at a grazing angle that
// the rounding of its axis would put behind; a box wholly below a one-sided receiver gives 0.
TEST(LightBvh, FlatNodesAndReceiverHorizonCullOnlyWhatGetsNoLight) {
  LightBounds b;  // a one-sided 1 x 1 quad at y = 2 facing down
  b.lo = vec3(-0.5f, 2.0f, -0.5f);
  b.hi = vec3(0.5f, 2.0f, 0.5f);
  b.w = vec3(0.0f, -1.0f, 0.0f);
  b.phi = 1.0f;
  b.cosTheta_o = 1.0f;
  b.cosTheta_e = 0.0f;
  LightRef behind, front;
  behind.p = vec3(0.3f, 2.05f, 0.0f);
  front.p = vec3(0.3f, 1.95f, 0.0f);
  EXPECT_GT(LightImportance(b, behind), 0.0f) << "the cone bound alone keeps it";
  b.flat = true;
  EXPECT_EQ(LightImportance(b, behind), 0.0f);
  EXPECT_GT(LightImportance(b, front), 0.0f);
  // The axis rounded 1e-4 rad off the lights' normal; a point 1e-5 in front of their plane,
  // 3.5 away, is lit at a grazing angle.
  b.w = glm::normalize(vec3(-1e-4f, -1.0f, 0.0f));
  LightRef grazing;
  grazing.p = vec3(3.5f, 2.0f - 1e-5f, 0.0f);
  EXPECT_GT(LightImportance(b, grazing), 0.0f);
  LightRef up, down;
  up.p = down.p = vec3(0.0f, 1.0f, 0.0f);
  up.n = vec3(0.0f, 1.0f, 0.0f);
  down.n = vec3(0.0f, -1.0f, 0.0f);
  up.twoSided = down.twoSided = false;
  EXPECT_GT(LightImportance(b, up), 0.0f);
  EXPECT_EQ(LightImportance(b, down), 0.0f);
  down.twoSided = true;
  EXPECT_GT(LightImportance(b, down), 0.0f);
}

// A leaf's importance bounds its light: wherever some point of the light faces the receiver
// (and, for a one-sided receiver, lies above its horizon), the importance is positive.
TEST(LightBvh, LeafImportanceIsPositiveWhereTheLightReachesTheReceiver) {
  LightTestScene ls = RandomLights(200, 21);
  std::vector<uint32_t> leafOf(ls.view.lightCount, 0);
  for (uint32_t k = 0; k < ls.view.lightTree.nodeCount; ++k)
    if (ls.view.lightNodes[k].IsLeaf()) leafOf[ls.view.lightNodes[k].Light()] = k;
  Uniform u(4);
  int reaching = 0, missed = 0;
  for (const LightRef& r : RandomRefs(60, 12)) {
    for (uint32_t i = 0; i < ls.view.lightCount; ++i) {
      bool reaches = false;
      for (int k = 0; k < 32 && !reaches; ++k) {
        LightLiSample s;
        if (!SampleOneLight(ls.view, i, r.p, u.Get2(), &s)) continue;
        float cosR = r.n == vec3(0.0f) ? 1.0f : glm::dot(s.wi, r.n);
        if (r.twoSided) cosR = std::fabs(cosR);
        reaches = cosR > 1e-3f;
      }
      if (!reaches) continue;
      ++reaching;
      if (!(NodeImportance(ls.view, leafOf[i], r) > 0.0f)) ++missed;
    }
  }
  EXPECT_GT(reaching, 1000);
  EXPECT_EQ(missed, 0) << "of " << reaching;
}

// Irradiance at a point under 30 small one-sided quads (some facing away) above its horizon:
// the sum of Lambert's polygon formula, whichever sampler chooses the quads; the pdf of each
// sample is what LightPdf gives for the same point from the same receiver.
TEST(LightBvh, NextEventEstimationThroughTheTreeIsUnbiased) {
  LightTestScene ls;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  double expected = 0.0;
  const vec3 x(0.1f, 0.0f, -0.2f), n = glm::normalize(vec3(0.1f, 1.0f, 0.05f));
  for (int i = 0; i < 30; ++i) {
    vec3 origin(2.0f * u(rng), 1.0f + 0.5f * u(rng), 2.0f * u(rng));
    vec3 e1 = 0.3f * vec3(1.0f, 0.2f * u(rng), 0.0f), e2 = 0.3f * vec3(0.0f, 0.2f * u(rng), 1.0f);
    if (i % 4 == 3) std::swap(e1, e2);  // faces up: away from x
    float radiance = 1.0f + 4.0f * (u(rng) + 1.0f);
    ls.AddQuad(Quad{origin, e1, e2}, ls.AddEmissive(vec3(radiance), false));
    glm::dvec3 qn = glm::normalize(glm::cross(glm::dvec3(e1), glm::dvec3(e2)));
    if (glm::dot(qn, glm::dvec3(x) - glm::dvec3(origin)) > 0.0)
      expected += LambertPolygonIrradiance(QuadCorners(ls.scene.desc.quads.back()),
                                           glm::dvec3(x), glm::dvec3(n), radiance);
  }
  ls.Build(LightSampler::kBvh);
  LightRef r = ReceiverRef(x, PackReceiver(n, false));
  for (LightSampler s : {LightSampler::kBvh, LightSampler::kPower, LightSampler::kUniform}) {
    ls.view.lightTree.sampler = uint32_t(s);
    Uniform rand(uint32_t(s) + 40);
    MeanAccumulator acc;
    int mismatches = 0;
    for (int k = 0; k < 200000; ++k) {
      LightLiSample ls2;
      double value = 0.0;
      float uLight = rand(), uRefresh = rand();
      if (SampleLightLi(ls.view, r, uLight, uRefresh, rand.Get2(), &ls2)) {
        value = double(ls2.L.x) * std::max(0.0f, glm::dot(ls2.wi, r.n)) / double(ls2.pdf);
        float pdf = LightPdf(ls.view, ls2.lightIndex, r, ls2.pLight, ls2.nLight);
        if (!(std::fabs(pdf - ls2.pdf) <= 1e-4f * ls2.pdf)) ++mismatches;
      }
      acc.Add(value);
    }
    MeanEstimate e = acc.Result();
    EXPECT_NEAR(e.mean, expected, kZ1e4 * e.stdError + 1e-5 * expected) << LightSamplerName(s);
    EXPECT_EQ(mismatches, 0) << LightSamplerName(s);
  }
}

}  // namespace
}  // namespace pt::test
