// The light BVH's importance (src/lights/light_bvh.h): BoxCosBound bounds the cosine over
// every point of its box, and under a plane of many downward lamps (the city block of
// benchmarks/scenes/make_many_lights.py, small) the tree chooses lamps nearly in proportion to
// the irradiance each delivers, where the bounding sphere's cones alone spread the choice over
// the neighbouring blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "src/lights/light_bvh_build.h"
#include "tests/light_bvh_test_util.h"

namespace pt::test {
namespace {

TEST(LightBvhImportance, BoxCosBoundHoldsOverTheWholeBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  int checked = 0, sharper = 0;
  for (int k = 0; k < 2000; ++k) {
    vec3 half(2.0f * u01(rng), 2.0f * u01(rng), k % 3 == 0 ? 0.0f : 2.0f * u01(rng));
    vec3 p = 6.0f * vec3(u(rng), u(rng), u(rng));  // the box is centred at the origin
    vec3 outside = glm::max(Abs(p) - half, vec3(0.0f));
    if (!(glm::dot(outside, outside) > 1e-4f)) continue;
    vec3 a = RandomUnit(rng);
    bool twoSided = k % 2 == 1;
    float bound = BoxCosBound(a, p, half, glm::length(outside), twoSided);
    if (bound < 0.5f) ++sharper;
    for (int j = 0; j < 64; ++j) {
      // Corners first (where the bound is tightest), then points inside.
      vec3 s = j < 8 ? vec3(j & 1 ? 1.0f : -1.0f, j & 2 ? 1.0f : -1.0f, j & 4 ? 1.0f : -1.0f)
                     : vec3(u(rng), u(rng), u(rng));
      vec3 w = glm::normalize(p - s * half);
      float c = glm::dot(a, w);
      if (twoSided) c = std::fabs(c);
      ASSERT_LE(c, bound + 1e-5f) << "box half " << half.x << " " << half.y << " " << half.z;
      ++checked;
    }
  }
  EXPECT_GT(checked, 60000);
  EXPECT_GT(sharper, 100) << "a bound that never bites tests nothing";
}

// Relative variance of choosing one of the lamps by the tree at r, against the exact
// (unshadowed) irradiance each delivers: sum_i E_i^2 / p_i / E^2 - 1, 0 for p_i ~ E_i.
double ChoiceRelativeVariance(const LightTestScene& ls, const LightRef& r) {
  double total = 0.0, second = 0.0;
  for (uint32_t i = 0; i < ls.view.lightCount; ++i) {
    const Quad& q = ls.scene.desc.quads[ls.scene.prims[ls.view.lights[i].prim].Index()];
    double e = LambertPolygonIrradiance(QuadCorners(q), glm::dvec3(r.p), glm::dvec3(r.n), 1.0);
    if (!(e > 0.0)) continue;
    double p = LightTreePmf(ls.view, r, i);
    if (!(p > 0.0)) return INFINITY;
    total += e;
    second += e * e / p;
  }
  return second / (total * total) - 1.0;
}

// 48 x 48 downward lamps 1 apart at height 3, seen from the ground below: the choice's
// relative variance stays below 0.5 (0.25 measured; pbrt-v4's importance, the bounding
// sphere's cones alone, gives 3.5: from inside a large node's bounding sphere it cannot tell
// the nearby lamps from those two blocks away).
TEST(LightBvhImportance, UnderAPlaneOfLampsTheTreeChoosesTheNearbyOnes) {
  LightTestScene ls;
  uint32_t lamp = ls.AddEmissive(vec3(1.0f), false);
  const int kSide = 48;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)  // normal cross(u, v) = -y
      ls.AddQuad(Quad{vec3(float(i) - 24.0f, 3.0f, float(j) - 24.0f), vec3(0.2f, 0.0f, 0.0f),
                      vec3(0.0f, 0.0f, 0.2f)}, lamp);
  ls.Build(LightSampler::kBvh);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  double sum = 0.0;
  const int kPoints = 40;
  for (int k = 0; k < kPoints; ++k) {
    LightRef r = ReceiverRef(vec3(u(rng), 0.0f, u(rng)), PackReceiver(vec3(0, 1, 0), false));
    sum += ChoiceRelativeVariance(ls, r);
  }
  EXPECT_LT(sum / kPoints, 0.5) << "mean relative variance of the choice";
}

}  // namespace
}  // namespace pt::test
