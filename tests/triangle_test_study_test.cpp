// --tri-test mt exists to measure what watertightness buys: Moller-Trumbore agrees with the
// watertight test away from edges, but rays aimed at shared edges slip through it.
#include <gtest/gtest.h>

#include <random>

#include "src/geometry/bvh.h"
#include "src/geometry/shapes.h"
#include "src/geometry/traverse.h"

namespace pt {
namespace {

struct Grid {
  std::vector<Triangle> triangles;
  std::vector<PrimRef> prims;
  std::vector<BvhNode> nodes;
  SceneView view;
};

// An n x n grid of triangle pairs over a sheared, tilted square: many shared edges in
// awkward float positions.
Grid MakeGrid(int n) {
  Grid g;
  auto point = [&](int i, int j) {
    float x = float(i) / n * 3.1f + 0.37f, z = float(j) / n * 2.9f - 1.13f;
    return vec3(x + 0.21f * z, 0.33f * x - 0.17f * z + 1.7f, z);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      g.triangles.push_back({point(i, j), point(i + 1, j), point(i + 1, j + 1)});
      g.triangles.push_back({point(i, j), point(i + 1, j + 1), point(i, j + 1)});
    }
  std::vector<Aabb> bounds;
  std::vector<PrimRef> unordered;
  for (uint32_t i = 0; i < g.triangles.size(); ++i) {
    unordered.push_back(PrimRef{PrimRef::Pack(ShapeType::kTriangle, i), 0, -1});
    bounds.push_back(TriangleBounds(g.triangles[i]));
  }
  BvhBuildResult bvh = BuildBvh(bounds, BvhBuildOptions{});
  g.nodes = bvh.nodes;
  for (uint32_t i : bvh.primOrder) g.prims.push_back(unordered[i]);
  g.view.nodes = g.nodes.data();
  g.view.prims = g.prims.data();
  g.view.triangles = g.triangles.data();
  g.view.nodeCount = uint32_t(g.nodes.size());
  g.view.primCount = uint32_t(g.prims.size());
  return g;
}

TEST(TriangleTestStudy, MollerTrumboreLeaksAtSharedEdgesWatertightDoesNot) {
  Grid g = MakeGrid(16);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  int leaksWatertight = 0, leaksMt = 0, rays = 200000;
  for (int k = 0; k < rays; ++k) {
    // A point on a random cell's diagonal (shared by its two triangles; the even triangle's
    // p0-p2 edge), from a random origin above.
    const Triangle& t = g.triangles[2 * size_t(u(rng) * (g.triangles.size() / 2 - 1))];
    float s = u(rng);
    vec3 target = t.p0 + s * (t.p2 - t.p0);  // the diagonal edge each pair shares
    vec3 origin = target + vec3(u(rng) - 0.5f, 2.0f + u(rng), u(rng) - 0.5f) * 3.0f;
    Ray ray{origin, glm::normalize(target - origin)};
    HitRecord hit;
    for (uint32_t test : {0u, 1u}) {
      g.view.triangleTest = test;
      if (!IntersectClosest(g.view, ray, kInfinity, &hit, nullptr)) ++(test ? leaksMt : leaksWatertight);
    }
  }
  EXPECT_EQ(leaksWatertight, 0);
  // The study's point: the fast test does leak (a measured rate, not a tolerance).
  EXPECT_GT(leaksMt, 0) << "of " << rays << " rays";
  RecordProperty("mt_leaks", leaksMt);
}

TEST(TriangleTestStudy, MollerTrumboreAgreesAwayFromEdges) {
  Triangle t{vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.05f, 0.45f);
  for (int k = 0; k < 10000; ++k) {
    vec3 target(u(rng), u(rng), 0.0f);
    vec3 origin = target + vec3(u(rng) - 0.25f, u(rng) - 0.25f, 1.0f + u(rng));
    Ray ray{origin, glm::normalize(target - origin)};
    float t1, t2;
    vec2 b1, b2;
    ASSERT_TRUE(IntersectTriangle(t, ray, kInfinity, &t1, &b1));
    ASSERT_TRUE(IntersectTriangleMollerTrumbore(t, ray, kInfinity, &t2, &b2));
    ASSERT_NEAR(t1, t2, 1e-5f * t1);
    ASSERT_NEAR(b1.x, b2.x, 1e-5f);
    ASSERT_NEAR(b1.y, b2.y, 1e-5f);
  }
}

}  // namespace
}  // namespace pt
