// BVH builder structure, traversal against brute force, and watertightness of closed meshes.
#include "src/geometry/bvh.h"

#include <gtest/gtest.h>

#include "tests/stat_test_util.h"
#include "tests/brute_force.h"

#include "tests/icosphere.h"

#include <cmath>
#include <ctime>
#include <map>
#include <random>

#include "src/geometry/shapes.h"
#include "src/geometry/traverse.h"

namespace pt {
namespace {

using test::RandomUnit;
using test::BruteForceClosest;

// Shapes plus their BVH, and a SceneView over them (as BuildScene would make one).
struct TestScene {
  std::vector<Triangle> triangles;
  std::vector<Quad> quads;
  std::vector<Sphere> spheres;
  std::vector<PrimRef> prims;
  BvhBuildResult bvh;
  SceneView view;

  void Build(const BvhBuildOptions& options = {}, int maxDepth = kBvhMaxDepth) {
    std::vector<PrimRef> input;
    std::vector<Aabb> bounds;
    auto add = [&](ShapeType type, uint32_t i, Aabb b) {
      input.push_back({PrimRef::Pack(type, i), uint32_t(input.size()), -1});
      bounds.push_back(b);
    };
    for (uint32_t i = 0; i < triangles.size(); ++i)
      add(ShapeType::kTriangle, i, PrimBounds(triangles[i]));
    for (uint32_t i = 0; i < quads.size(); ++i) add(ShapeType::kQuad, i, PrimBounds(quads[i]));
    for (uint32_t i = 0; i < spheres.size(); ++i)
      add(ShapeType::kSphere, i, PrimBounds(spheres[i]));
    bvh = BuildBvh(bounds, options, maxDepth);
    prims.resize(input.size());
    for (size_t i = 0; i < input.size(); ++i) prims[i] = input[bvh.primOrder[i]];
    view = SceneView{};
    view.nodes = bvh.nodes.data();
    view.nodeCount = uint32_t(bvh.nodes.size());
    view.prims = prims.data();
    view.primCount = uint32_t(prims.size());
    view.triangles = triangles.data();
    view.quads = quads.data();
    view.spheres = spheres.data();
  }
};


std::vector<Aabb> RandomBoxes(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f), s(0.0f, 0.5f);
  std::vector<Aabb> boxes(n);
  for (Aabb& b : boxes) {
    vec3 c(u(rng), u(rng), u(rng));
    b = Aabb::FromPoints(c - vec3(s(rng), s(rng), s(rng)), c + vec3(s(rng), s(rng), s(rng)));
  }
  return boxes;
}

// Checks the layout contract: every primitive in exactly one leaf, children adjacent and each
// node reached once, bounds nested, leaf sizes and depth within limits. Returns max leaf size.
uint32_t CheckStructure(const BvhBuildResult& r, const std::vector<Aabb>& boxes, int maxLeaf,
                        int maxDepth = kBvhMaxDepth) {
  size_t n = boxes.size();
  EXPECT_EQ(r.primOrder.size(), n);
  std::vector<int> seenPrim(n, 0), seenNode(r.nodes.size(), 0);
  for (uint32_t p : r.primOrder) {
    EXPECT_LT(p, n);
    if (p < n) ++seenPrim[p];
  }
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(seenPrim[i], 1) << "prim " << i;
  std::vector<int> covered(n, 0);
  uint32_t biggestLeaf = 0;
  int deepest = 0;
  std::vector<std::pair<uint32_t, int>> todo{{0u, 0}};
  while (!todo.empty()) {
    auto [index, depth] = todo.back();
    todo.pop_back();
    EXPECT_EQ(seenNode[index]++, 0) << "node " << index;
    const BvhNode& node = r.nodes[index];
    Aabb nb{node.boundsMin, node.boundsMax};
    if (node.IsLeaf()) {
      biggestLeaf = std::max(biggestLeaf, node.count);
      deepest = std::max(deepest, depth);
      EXPECT_LE(node.leftOrFirst + node.count, n);
      for (uint32_t i = node.leftOrFirst; i < node.leftOrFirst + node.count && i < n; ++i) {
        ++covered[i];
        EXPECT_TRUE(nb.Contains(boxes[r.primOrder[i]]));
      }
      continue;
    }
    if (node.leftOrFirst + 1 >= r.nodes.size()) {
      ADD_FAILURE() << "node " << index << " has children out of range";
      return 0;
    }
    for (uint32_t c = node.leftOrFirst; c <= node.leftOrFirst + 1; ++c) {
      EXPECT_TRUE(nb.Contains(Aabb{r.nodes[c].boundsMin, r.nodes[c].boundsMax}));
      todo.push_back({c, depth + 1});
    }
  }
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(covered[i], 1) << "slot " << i;
  for (size_t i = 0; i < r.nodes.size(); ++i) EXPECT_EQ(seenNode[i], 1) << "node " << i;
  EXPECT_EQ(r.maxDepth, deepest);
  EXPECT_LE(r.maxDepth, maxDepth);
  if (r.maxDepth < maxDepth) {
    EXPECT_LE(biggestLeaf, uint32_t(maxLeaf));
  }
  return biggestLeaf;
}

// ---- Builder ----

TEST(BvhBuild, EmptyInput) {
  BvhBuildResult r = BuildBvh({}, BvhBuildOptions{});
  ASSERT_EQ(r.nodes.size(), 1u);
  EXPECT_EQ(r.nodes[0].count, 0u);
  EXPECT_TRUE((Aabb{r.nodes[0].boundsMin, r.nodes[0].boundsMax}.IsEmpty()));
  EXPECT_TRUE(r.primOrder.empty());
  TestScene scene;
  scene.Build();
  HitRecord hit;
  TraversalCounters counters;
  Ray ray{vec3(0.0f), vec3(0, 0, 1)};
  EXPECT_FALSE(IntersectClosest(scene.view, ray, kInfinity, &hit, &counters));
  EXPECT_EQ(hit.prim, HitRecord::kNoHit);
  EXPECT_FALSE(IntersectAny(scene.view, ray, kInfinity, nullptr));
  scene.view.primCount = 1;  // a malformed view still must not loop or crash
  EXPECT_FALSE(IntersectClosest(scene.view, ray, kInfinity, &hit, nullptr));
}

TEST(BvhBuild, SinglePrimitive) {
  TestScene scene;
  scene.spheres.push_back(Sphere{vec3(0, 0, 5), 1.0f});
  scene.Build();
  ASSERT_EQ(scene.bvh.nodes.size(), 1u);
  EXPECT_EQ(scene.bvh.nodes[0].count, 1u);
  EXPECT_EQ(scene.bvh.maxDepth, 0);
  HitRecord hit;
  TraversalCounters counters;
  ASSERT_TRUE(
      IntersectClosest(scene.view, Ray{vec3(0.0f), vec3(0, 0, 1)}, kInfinity, &hit, &counters));
  EXPECT_FLOAT_EQ(hit.t, 4.0f);
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_EQ(counters.nodes, 1u);
  EXPECT_EQ(counters.prims, 1u);
  EXPECT_FALSE(IntersectAny(scene.view, Ray{vec3(0.0f), vec3(0, 0, -1)}, kInfinity, nullptr));
}

TEST(BvhBuild, IdenticalCentroidsSplitByIndex) {
  std::vector<Aabb> boxes(1000, Aabb::FromPoints(vec3(-1.0f), vec3(1.0f)));
  for (int leaf : {1, 4, 7}) {
    BvhBuildResult r = BuildBvh(boxes, BvhBuildOptions{leaf, 16});
    CheckStructure(r, boxes, leaf);
    EXPECT_LE(r.maxDepth, 11);
  }
  // Same centroid, different sizes: still a valid tree.
  std::vector<Aabb> nested;
  for (int i = 1; i <= 100; ++i)
    nested.push_back(Aabb::FromPoints(vec3(-float(i)), vec3(float(i))));
  CheckStructure(BuildBvh(nested, BvhBuildOptions{}), nested, 4);
}

TEST(BvhBuild, EveryPrimitiveOnceAndLeafSizeRespected) {
  std::vector<Aabb> boxes = RandomBoxes(5000, 21);
  for (int leaf : {1, 2, 4, 8}) {
    for (int bins : {2, 8, 16, 32}) {
      BvhBuildResult r = BuildBvh(boxes, BvhBuildOptions{leaf, bins});
      SCOPED_TRACE(testing::Message() << "leaf " << leaf << " bins " << bins);
      CheckStructure(r, boxes, leaf);
      EXPECT_LE(r.maxDepth, 40);
    }
  }
  // Deterministic.
  BvhBuildResult a = BuildBvh(boxes, {}), b = BuildBvh(boxes, {});
  EXPECT_EQ(a.primOrder, b.primOrder);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(0, memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)));
}

TEST(BvhBuild, DeepChainsDepthCapAndBadBounds) {
  // Geometrically spaced boxes defeat binning (the far box alone fills the top bins), which
  // makes a deep tree (33 levels for 300 boxes).
  std::vector<Aabb> boxes;
  for (int i = 0; i < 300; ++i) {
    float x = std::pow(1.3f, float(i));
    boxes.push_back(Aabb::FromPoints(vec3(x, 0, 0), vec3(x * 1.01f, 1, 1)));
  }
  BvhBuildResult r = BuildBvh(boxes, BvhBuildOptions{1, 16});
  CheckStructure(r, boxes, 1);
  EXPECT_GT(r.maxDepth, 25);
  // At the depth cap a node becomes a leaf whatever its size.
  r = BuildBvh(boxes, BvhBuildOptions{1, 16}, 5);
  EXPECT_EQ(r.maxDepth, 5);
  EXPECT_GT(CheckStructure(r, boxes, 1, 5), 1u);
  // NaN and infinite bounds (the caller should have dropped them) must not crash the build.
  std::vector<Aabb> bad = RandomBoxes(200, 22);
  bad[3].lo.x = NAN;
  bad[50] = Aabb::FromPoints(vec3(NAN), vec3(NAN));
  bad[70].hi = vec3(kInfinity);
  bad[90] = Aabb();
  r = BuildBvh(bad, BvhBuildOptions{});
  EXPECT_EQ(r.primOrder.size(), bad.size());
  std::vector<uint32_t> sorted = r.primOrder;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t i = 0; i < sorted.size(); ++i) EXPECT_EQ(sorted[i], i);
}

TEST(BvhBuild, BuildsQuicklyAt270kTriangles) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Aabb> boxes(270000);
  for (Aabb& b : boxes) {
    vec3 c = RandomUnit(rng) * (1.0f + 0.01f * u(rng));  // a surface, like a scanned mesh
    Triangle tri{c, c + 0.005f * vec3(u(rng), u(rng), u(rng)),
                 c + 0.005f * vec3(u(rng), u(rng), u(rng))};
    b = PrimBounds(tri);
  }
  // CPU time of this thread, so that a loaded machine does not fail the test.
  auto cpuSeconds = [] {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
  double start = cpuSeconds();
  BvhBuildResult r = BuildBvh(boxes, BvhBuildOptions{});
  double seconds = cpuSeconds() - start;
  std::printf("[          ] 270k build: %.1f ms CPU, %zu nodes, depth %d\n", seconds * 1e3,
              r.nodes.size(), r.maxDepth);
  EXPECT_EQ(r.primOrder.size(), boxes.size());
#if defined(NDEBUG) && !defined(__SANITIZE_ADDRESS__)
  EXPECT_LT(seconds, 0.6);
#endif
}

// ---- Traversal ----

void FillSoup(TestScene* scene, std::mt19937& rng, int triangles, int quads, int spheres,
              float maxSize) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  for (int i = 0; i < triangles; ++i) {
    vec3 c(u(rng), u(rng), u(rng));
    float s = maxSize * u01(rng) * u01(rng);
    Triangle tri{c + s * RandomUnit(rng), c + s * RandomUnit(rng), c + s * RandomUnit(rng)};
    if (glm::length(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0)) > 0.0f)
      scene->triangles.push_back(tri);
  }
  for (int i = 0; i < quads; ++i) {
    float s = maxSize * u01(rng);
    scene->quads.push_back(Quad{vec3(u(rng), u(rng), u(rng)), s * RandomUnit(rng),
                                s * (0.2f + u01(rng)) * RandomUnit(rng)});
  }
  for (int i = 0; i < spheres; ++i) {
    scene->spheres.push_back(
        Sphere{vec3(u(rng), u(rng), u(rng)), 0.01f + 0.2f * maxSize * u01(rng)});
  }
}

void CompareWithBruteForce(const TestScene& scene, std::mt19937& rng, int rays) {
  std::uniform_real_distribution<float> u(-1.5f, 1.5f), u01(0.0f, 1.0f);
  int hits = 0;
  TraversalCounters counters;
  for (int i = 0; i < rays; ++i) {
    Ray ray{vec3(u(rng), u(rng), u(rng)), RandomUnit(rng)};
    float tMax = i % 5 == 0 ? 3.0f * u01(rng) : kInfinity;
    HitRecord bvh, brute;
    bool hitBvh = IntersectClosest(scene.view, ray, tMax, &bvh, &counters);
    bool hitBrute = BruteForceClosest(scene.view, ray, tMax, &brute);
    ASSERT_EQ(hitBvh, hitBrute) << "ray " << i;
    ASSERT_EQ(IntersectAny(scene.view, ray, tMax, nullptr), hitBvh) << "ray " << i;
    if (!hitBvh) continue;
    ++hits;
    ASSERT_EQ(bvh.t, brute.t) << "ray " << i;  // the same float: same tests, same minimum
    if (bvh.prim != brute.prim) {  // an exact tie: the other primitive must give the same t
      float t;
      vec2 uv;
      ASSERT_TRUE(IntersectPrim(scene.view, bvh.prim, ray, kInfinity, &t, &uv));
      ASSERT_EQ(t, brute.t);
    } else {
      ASSERT_EQ(bvh.uv, brute.uv);
    }
    // Nothing strictly before the closest hit; the hit itself just beyond it.
    ASSERT_FALSE(IntersectAny(scene.view, ray, bvh.t, nullptr)) << "ray " << i;
    ASSERT_TRUE(IntersectAny(scene.view, ray, NextFloatUp(bvh.t), nullptr)) << "ray " << i;
  }
  EXPECT_GT(hits, rays / 20);
  EXPECT_GT(counters.nodes, uint32_t(rays));
  EXPECT_GT(counters.prims, 0u);
}

TEST(BvhTraversal, MatchesBruteForceOnSoups) {
  struct Soup {
    int triangles, quads, spheres;
    float size;
    int leaf;
  };
  const Soup soups[] = {{1500, 0, 0, 0.3f, 4},
                        {900, 150, 80, 0.4f, 4},
                        {300, 40, 300, 1.5f, 2},
                        {600, 300, 100, 0.25f, 8}};
  std::mt19937 rng(31);
  for (const Soup& soup : soups) {
    TestScene scene;
    FillSoup(&scene, rng, soup.triangles, soup.quads, soup.spheres, soup.size);
    scene.Build(BvhBuildOptions{soup.leaf, 16});
    SCOPED_TRACE(testing::Message() << "soup of " << scene.prims.size());
    CompareWithBruteForce(scene, rng, 27000);
  }
}

TEST(BvhTraversal, DeepAndDepthCappedTreesMatchBruteForce) {
  TestScene scene;
  for (int i = 0; i < 200; ++i) {  // geometric spacing: a 30-level tree
    float x = std::pow(1.25f, float(i)) * 1e-12f;
    scene.spheres.push_back(Sphere{vec3(x, 0, 0), x * 0.05f});
    scene.quads.push_back(Quad{vec3(x, -x, -x), vec3(0, 2 * x, 0), vec3(0, 0, 2 * x)});
  }
  for (int maxDepth : {kBvhMaxDepth, 4}) {
    scene.Build(BvhBuildOptions{1, 16}, maxDepth);
    std::mt19937 rng(32);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 4000; ++i) {
      float scale = std::pow(1.25f, float(i % 200)) * 1e-12f;
      Ray ray{vec3(u(rng), u(rng), u(rng)) * scale * 3.0f, RandomUnit(rng)};
      HitRecord bvh, brute;
      ASSERT_EQ(IntersectClosest(scene.view, ray, kInfinity, &bvh, nullptr),
                BruteForceClosest(scene.view, ray, kInfinity, &brute));
      if (bvh.prim != HitRecord::kNoHit) {
        ASSERT_EQ(bvh.t, brute.t);
      }
    }
  }
}

// ---- Watertightness ----

// Closed meshes with shared vertices: a subdivided icosphere and a tessellated cube.
void AddIcosphere(TestScene* scene, vec3 center, float radius, int subdivisions) {
  for (const Triangle& t : test::IcosphereTriangles(glm::dvec3(center), radius, subdivisions))
    scene->triangles.push_back(t);
}

void AddTessellatedCube(TestScene* scene, vec3 center, float half, int n) {
  auto vertex = [&](int i, int j, int k) {  // one float per grid index: shared exactly
    auto c = [&](int x) { return -half + 2.0f * half * float(x) / float(n); };
    return center + vec3(c(i), c(j), c(k));
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          glm::ivec3 idx[4];
          for (int q = 0; q < 4; ++q) {
            idx[q][axis] = side;
            idx[q][(axis + 1) % 3] = i + (q == 1 || q == 2);
            idx[q][(axis + 2) % 3] = j + (q >= 2);
          }
          vec3 p[4];
          for (int q = 0; q < 4; ++q) p[q] = vertex(idx[q].x, idx[q].y, idx[q].z);
          bool flip = (i + j) % 2 == 1;  // alternate the diagonal
          scene->triangles.push_back(flip ? Triangle{p[0], p[1], p[3]}
                                          : Triangle{p[0], p[1], p[2]});
          scene->triangles.push_back(flip ? Triangle{p[1], p[2], p[3]}
                                          : Triangle{p[0], p[2], p[3]});
        }
      }
    }
  }
}

// Rays from outside aimed exactly at vertices and at points on edges, continuing towards an
// interior point so they enter the (convex) mesh there: each must hit near the aimed point,
// never slip through to the far side or miss.
int TraceAtEdges(const TestScene& scene, vec3 center, float innerRadius, int rays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::uniform_int_distribution<size_t> pick(0, scene.triangles.size() - 1);
  int failures = 0;
  for (int i = 0; i < rays; ++i) {
    const Triangle& tri = scene.triangles[pick(rng)];
    const vec3 corner[3] = {tri.p0, tri.p1, tri.p2};
    int e = int(u01(rng) * 3.0f) % 3;
    vec3 target = i % 4 == 0 ? corner[e] : glm::mix(corner[e], corner[(e + 1) % 3], u01(rng));
    vec3 inner = center + RandomUnit(rng) * (innerRadius * std::cbrt(u01(rng)));
    float dist = 0.05f + 3.0f * u01(rng);
    vec3 o = target + glm::normalize(target - inner) * dist;
    Ray ray{o, glm::normalize(target - o)};
    HitRecord hit;
    bool ok = IntersectClosest(scene.view, ray, kInfinity, &hit, nullptr) &&
              fabsf(hit.t - glm::length(target - o)) <= 1e-4f * (1.0f + dist);
    if (i % 8 == 0) ok = ok && IntersectAny(scene.view, ray, kInfinity, nullptr);
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << "ray " << i << " hit " << hit.prim << " t " << hit.t;
  }
  return failures;
}

TEST(BvhTraversal, WatertightAtSharedEdgesAndVertices) {
  TestScene sphere;
  AddIcosphere(&sphere, vec3(0.3f, -0.2f, 0.1f), 1.0f, 4);
  sphere.Build();
  EXPECT_EQ(TraceAtEdges(sphere, vec3(0.3f, -0.2f, 0.1f), 0.5f, 450000, 41), 0);

  TestScene cube;
  vec3 center(0.1f, 0.7f, -0.4f);
  AddTessellatedCube(&cube, center, 1.0f, 12);
  cube.Build();
  EXPECT_EQ(TraceAtEdges(cube, center, 0.8f, 450000, 42), 0);

  // Axis-aligned rays through the cube's grid points and edge midpoints (edge functions exactly 0).
  int failures = 0, rays = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (int i = 0; i <= 48; ++i) {
      for (int j = 0; j <= 48; ++j) {
        for (float dir : {-1.0f, 1.0f}) {
          vec3 o = center, d(0.0f);
          o[axis] -= 5.0f * dir;
          d[axis] = dir;
          o[(axis + 1) % 3] = center[(axis + 1) % 3] - 1.0f + 2.0f * float(i) / 48.0f;
          o[(axis + 2) % 3] = center[(axis + 2) % 3] - 1.0f + 2.0f * float(j) / 48.0f;
          HitRecord hit;
          ++rays;
          if (!IntersectClosest(cube.view, Ray{o, d}, kInfinity, &hit, nullptr) ||
              fabsf(hit.t - 4.0f) > 1e-5f) {
            ++failures;
          }
        }
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << rays;
  EXPECT_GE(900000 + rays, 910000);
}

}  // namespace
}  // namespace pt
