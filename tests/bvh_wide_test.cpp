// The wide layout and the SBVH builder against brute force: random and in-plane (grazing) rays
// on soups of every shape, closest hit identical across layouts and builders (node order never
// decides), any-hit agreeing with closest-hit, quantised child boxes conservative, empty and
// one-triangle scenes, NaN and infinite rays.
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "src/geometry/bvh_wide.h"
#include "tests/brute_force.h"
#include "tests/hard_geometry_util.h"

namespace pt {
namespace {

using hard::BuildShapes;
using hard::ShapeScene;
using test::BruteForceClosest;
// Uniform on the sphere (z and azimuth uniform).
vec3 RandomDir(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float z = 1.0f - 2.0f * u(rng), phi = 6.2831853f * u(rng), r = std::sqrt(1.0f - z * z);
  return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

BvhBuildOptions Options(BvhLayout layout, BvhBuilder builder) {
  BvhBuildOptions o;
  o.layout = layout;
  o.builder = builder;
  o.threads = 2;
  return o;
}

struct Soup {
  std::vector<Triangle> tris;
  std::vector<Quad> quads;
  std::vector<Sphere> spheres;
};

// Small triangles on a sphere (like a scanned mesh), long thin ones across it (where spatial
// splits pay), quads and spheres.
Soup MakeSoup(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), u01(0.0f, 1.0f);
  Soup s;
  for (int i = 0; i < 1500; ++i) {
    vec3 c = RandomDir(rng);
    float r = 0.08f * u01(rng);
    s.tris.push_back({c + r * RandomDir(rng), c + r * RandomDir(rng), c + r * RandomDir(rng)});
  }
  for (int i = 0; i < 60; ++i) {
    vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    s.tris.push_back({a, b, b + 0.02f * RandomDir(rng)});
  }
  for (int i = 0; i < 40; ++i)
    s.quads.push_back({vec3(u(rng), u(rng), u(rng)), 0.3f * RandomDir(rng), 0.2f * RandomDir(rng)});
  for (int i = 0; i < 40; ++i) s.spheres.push_back({vec3(u(rng), u(rng), u(rng)), 0.1f * u01(rng)});
  return s;
}

ShapeScene BuildSoup(const Soup& s, BvhLayout layout, BvhBuilder builder) {
  return BuildShapes(s.tris, s.quads, s.spheres, Options(layout, builder));
}

// Random rays from inside the soup's box, and rays lying in a random triangle's plane aimed at
// one of its vertices or edge midpoints (grazing: the hard case of the box and triangle tests).
std::vector<Ray> MakeRays(const Soup& s, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f), u01(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    if (i % 2 == 0) {
      rays.push_back(Ray{vec3(u(rng), u(rng), u(rng)), RandomDir(rng)});
      continue;
    }
    const Triangle& t = s.tris[rng() % s.tris.size()];
    vec3 e1 = t.p1 - t.p0, e2 = t.p2 - t.p0;
    vec3 target = i % 4 == 1 ? t.p0 : 0.5f * (t.p1 + t.p2);
    vec3 origin = t.p0 + (2.0f * u(rng)) * e1 + (2.0f * u(rng)) * e2;  // in the plane
    vec3 d = target - origin;
    if (glm::length(d) == 0.0f) d = e1;
    rays.push_back(Ray{origin, glm::normalize(d)});
  }
  return rays;
}

class WideAndSbvh : public testing::TestWithParam<std::pair<BvhLayout, BvhBuilder>> {};

TEST_P(WideAndSbvh, MatchesBruteForceOnRandomAndGrazingRays) {
  const Soup soup = MakeSoup(7);
  ShapeScene scene = BuildSoup(soup, GetParam().first, GetParam().second);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int hits = 0;
  const std::vector<Ray> rays = MakeRays(soup, 20000, 3);
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& ray = rays[i];
    float tMax = i % 5 == 0 ? 3.0f * u01(rng) : kInfinity;
    HitRecord bvh, brute;
    bool hitBvh = IntersectClosest(scene.view, ray, tMax, &bvh, nullptr);
    ASSERT_EQ(hitBvh, BruteForceClosest(scene.view, ray, tMax, &brute)) << "ray " << i;
    ASSERT_EQ(IntersectAny(scene.view, ray, tMax, nullptr), hitBvh) << "ray " << i;
    if (!hitBvh) continue;
    ++hits;
    ASSERT_EQ(bvh.t, brute.t) << "ray " << i;
    // Ties (and SBVH's duplicate references) resolve to the same shape.
    ASSERT_EQ(scene.view.prims[bvh.prim].tagIndex, scene.view.prims[brute.prim].tagIndex) << i;
    ASSERT_FALSE(IntersectAny(scene.view, ray, bvh.t, nullptr)) << "ray " << i;
  }
  EXPECT_GT(hits, int(rays.size()) / 10);
}

INSTANTIATE_TEST_SUITE_P(
    Bvh, WideAndSbvh,
    testing::Values(std::pair{BvhLayout::kWide, BvhBuilder::kSah},
                    std::pair{BvhLayout::kBinary, BvhBuilder::kSbvh},
                    std::pair{BvhLayout::kWide, BvhBuilder::kSbvh}),
    [](const auto& info) {
      return std::string(BvhLayoutName(info.param.first)) + "_" + BvhBuilderName(info.param.second);
    });

// The closest hit is a property of the scene, not of the tree: every layout and builder gives
// the same distance, shape and barycentrics, bit for bit (CPU determinism, CPU/GPU agreement).
TEST(BvhWide, ClosestHitIsIndependentOfLayoutAndBuilder) {
  const Soup soup = MakeSoup(21);
  ShapeScene ref = BuildSoup(soup, BvhLayout::kBinary, BvhBuilder::kSah);
  const std::pair<BvhLayout, BvhBuilder> others[] = {{BvhLayout::kWide, BvhBuilder::kSah},
                                                     {BvhLayout::kBinary, BvhBuilder::kSbvh},
                                                     {BvhLayout::kWide, BvhBuilder::kSbvh}};
  const std::vector<Ray> rays = MakeRays(soup, 10000, 5);
  for (const auto& [layout, builder] : others) {
    ShapeScene other = BuildSoup(soup, layout, builder);
    SCOPED_TRACE(std::string(BvhLayoutName(layout)) + " " + BvhBuilderName(builder));
    for (size_t i = 0; i < rays.size(); ++i) {
      HitRecord a, b;
      bool hitA = IntersectClosest(ref.view, rays[i], kInfinity, &a, nullptr);
      ASSERT_EQ(IntersectClosest(other.view, rays[i], kInfinity, &b, nullptr), hitA) << i;
      if (!hitA) continue;
      ASSERT_EQ(a.t, b.t) << i;
      ASSERT_EQ(ref.view.prims[a.prim].tagIndex, other.view.prims[b.prim].tagIndex) << i;
      ASSERT_EQ(a.uv, b.uv) << i;
    }
  }
}

// The GPU's closest-hit walk takes each node's nearest hit interior child first
// (kWideNearestFirst); run here on the host through the scalar node test, it must find brute
// force's hit, and the octant-order walk's, on random and grazing rays, for both builders.
TEST(BvhWide, NearestChildFirstWalkMatchesBruteForce) {
  const Soup soup = MakeSoup(7);
  const std::vector<Ray> rays = MakeRays(soup, 20000, 9);
  for (BvhBuilder builder : {BvhBuilder::kSah, BvhBuilder::kSbvh}) {
    ShapeScene scene = BuildSoup(soup, BvhLayout::kWide, builder);
    SCOPED_TRACE(BvhBuilderName(builder));
    TraversalCounters nearestFirst{}, octantOrder{};
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      PrimLeaf<TraceMode::kClosest> a(scene.view, rays[i]), b(scene.view, rays[i]);
      float tA = kInfinity, tB = kInfinity;
      Traverse<TraceMode::kClosest, decltype(a), true>(SceneWideBvh(scene.view), rays[i], &tA, a,
                                                      &nearestFirst);
      Traverse<TraceMode::kClosest, decltype(b), false>(SceneWideBvh(scene.view), rays[i], &tB, b,
                                                       &octantOrder);
      HitRecord brute;
      const bool hit = test::BruteForceClosest(scene.view, rays[i], kInfinity, &brute);
      ASSERT_EQ(a.prim != HitRecord::kNoHit, hit) << "ray " << i;
      ASSERT_EQ(b.prim != HitRecord::kNoHit, hit) << "ray " << i;
      if (!hit) continue;
      ++hits;
      ASSERT_EQ(tA, brute.t) << "ray " << i;
      ASSERT_EQ(tB, brute.t) << "ray " << i;
      ASSERT_EQ(scene.view.prims[a.prim].tagIndex, scene.view.prims[brute.prim].tagIndex) << i;
      ASSERT_EQ(a.uv, b.uv) << "ray " << i;
    }
    EXPECT_GT(hits, int(rays.size()) / 10);
    // The two orders really differ: otherwise this test would not exercise the new one.
    EXPECT_NE(nearestFirst.nodes, octantOrder.nodes);
  }
}

// Overlapping coplanar triangles and quads (a rug on a floor, decals): their computed hit
// distances differ only by rounding, up to ~1e-5 before the plane's exact distance, which is
// also their boxes' entry distance. With --tri-test box-clamped every tree must still return
// brute force's hit: a node is never culled by a hit that its own shape's distance, raised to
// its box entry (ShapeBoxEntry), could beat. (With the plain watertight test 6-13% of these
// rays' hits differ from brute force's: the known exception of docs/bvh.md.)
TEST(BvhWide, ClosestHitOnCoincidentSurfacesIsIndependentOfTheTree) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f), u01(0.0f, 1.0f);
  const float plane = 0.3719f;
  Soup soup;
  for (int i = 0; i < 400; ++i) {
    auto p = [&] { return vec3(u(rng), plane, u(rng)); };
    soup.tris.push_back({p(), p(), p()});
  }
  for (int i = 0; i < 40; ++i) {
    soup.quads.push_back({vec3(u(rng), plane, u(rng)), vec3(3.0f * u01(rng), 0.0f, 0.0f),
                          vec3(0.0f, 0.0f, 3.0f * u01(rng))});
  }
  std::vector<Ray> rays;
  for (int i = 0; i < 20000; ++i) {
    const float height = (i % 2 ? 1.0f : -1.0f) * (0.005f + 0.3f * u01(rng));
    vec3 d = RandomDir(rng);
    if ((d.y < 0.0f) == (height < 0.0f)) d.y = -d.y;  // towards the plane
    rays.push_back(Ray{vec3(u(rng), plane + height, u(rng)), d});
  }
  for (const auto& [layout, builder] : {std::pair{BvhLayout::kBinary, BvhBuilder::kSah},
                                        std::pair{BvhLayout::kWide, BvhBuilder::kSah},
                                        std::pair{BvhLayout::kWide, BvhBuilder::kSbvh}}) {
    SCOPED_TRACE(std::string(BvhLayoutName(layout)) + " " + BvhBuilderName(builder));
    ShapeScene scene = BuildSoup(soup, layout, builder);
    scene.view.triangleTest = kTriTestBoxClamped;
    int hits = 0, differ = 0;
    for (const Ray& ray : rays) {
      HitRecord bvh, brute;
      const bool hit = IntersectClosest(scene.view, ray, kInfinity, &bvh, nullptr);
      ASSERT_EQ(hit, BruteForceClosest(scene.view, ray, kInfinity, &brute));
      if (!hit) continue;
      ++hits;
      differ += bvh.t != brute.t || scene.view.prims[bvh.prim].tagIndex !=
                                        scene.view.prims[brute.prim].tagIndex;
    }
    EXPECT_EQ(differ, 0) << "of " << hits << " hits";
    EXPECT_GT(hits, int(rays.size()) / 2);
  }
}

Aabb WideChildBox(const WideBvhNode& n, int slot) {
  Aabb box;
  for (int a = 0; a < 3; ++a) {
    float scale = std::ldexp(1.0f, int(n.exponent[a]) - 127);
    box.lo[a] = n.origin[a] + float(n.qlo[a][slot]) * scale;
    box.hi[a] = n.origin[a] + float(n.qhi[a][slot]) * scale;
  }
  return box;
}

// Entry distance of a ray into a box, in double: the largest near-plane distance, at least 0.
double EntryDistance(const Aabb& box, const Ray& ray) {
  double entry = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double lo = (double(box.lo[a]) - ray.o[a]) / ray.d[a];
    const double hi = (double(box.hi[a]) - ray.o[a]) / ray.d[a];
    entry = std::max(entry, std::min(lo, hi));
  }
  return entry;
}

// The node test's nearest child: a hit interior child (none exactly when no interior child is
// hit) whose box the ray enters no later than any other hit interior child's, up to the test's
// conservative widening of its distances.
TEST(BvhWide, NodeTestNamesTheNearestHitInteriorChild) {
  const Soup soup = MakeSoup(13);
  ShapeScene scene = BuildSoup(soup, BvhLayout::kWide, BvhBuilder::kSah);
  const std::vector<WideBvhNode>& nodes = scene.scene.wideNodes;
  const std::vector<Ray> rays = MakeRays(soup, 2000, 15);
  int choices = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const detail::WideRay r = detail::MakeWideRay(rays[i]);
    for (size_t index = 0; index < nodes.size(); ++index) {
      const WideBvhNode& node = nodes[index];
      uint32_t nearest = ~0u;
      const uint32_t hits = detail::IntersectWideChildrenScalar<true>(
          detail::LoadWideNode(&node), r, kInfinity, &nearest);
      const uint32_t interiorHits = hits & 0xff000000u;
      ASSERT_EQ(nearest == 0, interiorHits == 0) << "ray " << i << " node " << index;
      if (interiorHits == 0) continue;
      ASSERT_TRUE(nearest >= 24 && ((interiorHits >> nearest) & 1u)) << i << " " << index;
      const auto entry = [&](uint32_t bit) {
        return EntryDistance(WideChildBox(node, int((bit - 24u) ^ r.octInv)), rays[i]);
      };
      const double nearestEntry = entry(nearest);
      for (uint32_t bit = 24; bit < 32; ++bit) {
        if (bit == nearest || !((interiorHits >> bit) & 1u)) continue;
        ++choices;
        ASSERT_LE(nearestEntry, entry(bit) + 1e-5 * (1.0 + entry(bit)))
            << "ray " << i << " node " << index << " bit " << bit;
      }
    }
  }
  EXPECT_GT(choices, 1000);  // nodes where more than one interior child was hit
}

bool BoxContains(const Aabb& outer, const Aabb& inner) {
  for (int a = 0; a < 3; ++a)
    if (inner.lo[a] < outer.lo[a] || inner.hi[a] > outer.hi[a]) return false;
  return true;
}

// Exact bounds of the primitives under wide node `index`; checks every quantised child box
// contains them (decoded in double-free float: origin + q * 2^e is exact for 8-bit q). Counts
// the primitive slots reached.
Aabb CheckWideSubtree(const Scene& scene, const SceneView& view, uint32_t index,
                      std::vector<int>* reached) {
  const WideBvhNode& n = scene.wideNodes[index];
  Aabb all;
  uint32_t interior = 0;
  for (int slot = 0; slot < 8; ++slot) {
    const uint32_t meta = n.meta[slot];
    if (meta == 0) continue;
    Aabb child;
    if ((n.innerMask >> slot) & 1u) {
      child = CheckWideSubtree(scene, view, n.childBase + interior++, reached);
    } else {
      for (uint32_t k = 0; k < 24; ++k) {
        if ((((meta >> 5) << (meta & 31u)) >> k) & 1u) {
          child.Extend(PrimBounds(view, n.primBase + k));
          ++(*reached)[n.primBase + k];
        }
      }
    }
    EXPECT_TRUE(BoxContains(WideChildBox(n, slot), child)) << "node " << index << " slot " << slot;
    all.Extend(child);
  }
  return all;
}

TEST(BvhWide, QuantisedChildBoxesAreConservative) {
  Soup soup = MakeSoup(5);
  // Far from the origin and tiny: quantisation steps are coarse relative to the boxes.
  for (Triangle& t : soup.tris) {
    t.p0 = 1000.0f + 0.01f * t.p0;
    t.p1 = 1000.0f + 0.01f * t.p1;
    t.p2 = 1000.0f + 0.01f * t.p2;
  }
  ShapeScene s = BuildShapes(soup.tris, {}, {}, Options(BvhLayout::kWide, BvhBuilder::kSah));
  ASSERT_FALSE(s.scene.wideNodes.empty());
  std::vector<int> reached(s.view.primCount, 0);
  CheckWideSubtree(s.scene, s.view, 0, &reached);
  for (size_t i = 0; i < reached.size(); ++i) ASSERT_EQ(reached[i], 1) << "primitive " << i;
}

// The meta byte's rule, one slot at a time: meta >> 5 at bit meta & 31, interior bits (24 and
// up) with their slot mirrored by the octant.
uint32_t SlotHitBitsOneByOne(uint32_t meta4, uint32_t k, uint32_t octInv) {
  const uint32_t meta = (meta4 >> (8u * k)) & 0xffu;
  uint32_t bit = meta & 31u;
  bit = bit >= 24u ? bit ^ octInv : bit;
  return (meta >> 5) << bit;
}

// Both node tests decode a node half's four meta bytes at once; that must set the same bits as
// the rule applied byte by byte, for every meta byte, octant and slot position.
TEST(BvhWide, FourSlotDecodeMatchesThePerSlotDecode) {
  std::mt19937 rng(7);
  for (uint32_t octInv = 0; octInv < 8; ++octInv) {
    for (uint32_t meta = 0; meta < 256; ++meta) {
      for (uint32_t k = 0; k < 4; ++k) {
        // The byte under test at position k among random neighbours.
        uint32_t meta4 = rng();
        meta4 = (meta4 & ~(0xffu << (8u * k))) | (meta << (8u * k));
        EXPECT_EQ(detail::SlotBits4::Decode(meta4, octInv).HitBits(k),
                  SlotHitBitsOneByOne(meta4, k, octInv))
            << "meta " << meta << ", octInv " << octInv << ", slot " << k;
      }
    }
  }
}

TEST(BvhWide, EmptyAndOneTriangleScenes) {
  for (BvhBuilder builder : {BvhBuilder::kSah, BvhBuilder::kSbvh}) {
    ShapeScene empty = BuildShapes({}, {}, {}, Options(BvhLayout::kWide, builder));
    HitRecord hit;
    Ray ray{vec3(0.0f), vec3(0, 0, -1)};
    EXPECT_FALSE(IntersectClosest(empty.view, ray, kInfinity, &hit, nullptr));
    EXPECT_FALSE(IntersectAny(empty.view, ray, kInfinity, nullptr));
    ShapeScene one = BuildShapes({Triangle{vec3(-1, -1, -2), vec3(1, -1, -2), vec3(0, 1, -2)}}, {},
                                 {}, Options(BvhLayout::kWide, builder));
    ASSERT_TRUE(IntersectClosest(one.view, ray, kInfinity, &hit, nullptr));
    EXPECT_EQ(hit.t, 2.0f);
    EXPECT_TRUE(IntersectAny(one.view, ray, kInfinity, nullptr));
    EXPECT_FALSE(IntersectAny(one.view, ray, 1.5f, nullptr));
    EXPECT_FALSE(IntersectClosest(one.view, Ray{vec3(0.0f), vec3(0, 0, 1)}, kInfinity, &hit, nullptr));
  }
}

TEST(BvhWide, NanAndInfiniteRaysHitNothing) {
  const Soup soup = MakeSoup(9);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
  const Ray bad[] = {{vec3(nan, 0, 0), vec3(0, 0, 1)}, {vec3(0.0f), vec3(nan, 0, 0)},
                     {vec3(0.0f), vec3(nan)},          {vec3(inf, 0, 0), vec3(-1, 0, 0)},
                     {vec3(0.0f), vec3(0, inf, 0)}};
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    ShapeScene s = BuildSoup(soup, layout, BvhBuilder::kSah);
    for (const Ray& ray : bad) {
      HitRecord hit;
      EXPECT_FALSE(IntersectClosest(s.view, ray, kInfinity, &hit, nullptr)) << BvhLayoutName(layout);
      EXPECT_FALSE(IntersectAny(s.view, ray, kInfinity, nullptr)) << BvhLayoutName(layout);
    }
    // A NaN tMax culls nothing it should not: the ray still finds what an infinite one finds
    // or nothing at all, never a crash.
    HitRecord hit;
    IntersectClosest(s.view, Ray{vec3(0.0f), vec3(0, 0, 1)}, nan, &hit, nullptr);
  }
}

// SBVH trades build time for a lower SAH cost where primitives straddle split planes; its
// duplicated references stay within the budget.
TEST(BvhWide, SbvhLowersTheSahCostOfLongTriangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Triangle> tris;
  for (int i = 0; i < 3000; ++i) {
    vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    tris.push_back({a, b, a + 0.01f * RandomDir(rng)});
  }
  ShapeScene sah = BuildShapes(tris, {}, {}, Options(BvhLayout::kBinary, BvhBuilder::kSah));
  ShapeScene sbvh = BuildShapes(tris, {}, {}, Options(BvhLayout::kBinary, BvhBuilder::kSbvh));
  EXPECT_LT(sbvh.scene.bvhSahCost, 0.9 * sah.scene.bvhSahCost);
  EXPECT_GT(sbvh.view.primCount, sah.view.primCount);
  EXPECT_LE(sbvh.view.primCount, 2 * sah.view.primCount);
}

// The collapse runs subtrees as tasks on several threads: the nodes, primitive order, depth and
// cost must be the same bits as on one thread, and every primitive must land in exactly one leaf.
TEST(BvhWide, ParallelCollapseGivesTheSameNodesAsOneThread) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Aabb> bounds;
  for (int i = 0; i < 40000; ++i) {  // well above the collapse's task size (4096 primitives)
    vec3 c(u(rng), u(rng), u(rng)), e = 0.01f * (vec3(u(rng), u(rng), u(rng)) + 1.0f);
    bounds.push_back(Aabb{c - e, c + e});
  }
  BvhBuildOptions options;
  options.maxLeafSize = 1;
  options.threads = 2;
  const BvhBuildResult binary = BuildBvh(bounds, options);
  const WideBvhResult one = CollapseToWide(binary, bounds, 1);
  for (int threads : {2, 3}) {
    const WideBvhResult many = CollapseToWide(binary, bounds, threads);
    ASSERT_EQ(many.nodes.size(), one.nodes.size()) << threads;
    EXPECT_EQ(std::memcmp(many.nodes.data(), one.nodes.data(),
                          one.nodes.size() * sizeof(WideBvhNode)), 0) << threads;
    EXPECT_EQ(many.primOrder, one.primOrder) << threads;
    EXPECT_EQ(many.maxDepth, one.maxDepth) << threads;
    EXPECT_EQ(many.sahCost, one.sahCost) << threads;
  }
  std::vector<int> seen(bounds.size(), 0);
  for (uint32_t p : one.primOrder) ++seen[p];
  for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;
  EXPECT_GT(one.nodes.size(), bounds.size() / 24);  // a tree, not one leaf per primitive run
}

}  // namespace
}  // namespace pt
