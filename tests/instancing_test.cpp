// Instancing (src/scene/instances.h): a scene whose meshes are placed by instances renders as the
// same scene flattened into world space (bit for bit under identity placements, statistically
// under rotation, non-uniform scale and mirroring), its two-level queries find the brute-force
// hits, and moving an instance then rebuilding the top level equals building afresh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "src/geometry/instance.h"
#include "src/geometry/traverse.h"
#include "src/integrator/render_session.h"
#include "src/scene/instances.h"
#include "tests/render_test_util.h"
#include "tests/test_util.h"
#include "tests/welch.h"

namespace pt::test {
namespace {

// A floor, a lamp quad and the instances `objects` adds; the mesh table holds the torus and
// icosphere file as "shapes" and the same file shrunk and lifted as "small".
std::string InstancedScene(const std::string& objects, int size = 48, int spp = 8, int seed = 1) {
  std::string file = SourcePath("scenes/meshes/smooth_shapes.glb");
  return R"({"format": 1,
    "render": {"width": )" + std::to_string(size) + R"(, "height": )" + std::to_string(size) +
         R"(, "spp": )" + std::to_string(spp) + R"(, "max_depth": 4, "seed": )" +
         std::to_string(seed) + R"(},
    "camera": {"position": [0, 1, 3.9], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov_y": 45},
    "background": [0.05, 0.05, 0.05],
    "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                  "red": {"type": "diffuse", "albedo": [0.6, 0.1, 0.1]},
                  "lamp": {"type": "emissive", "radiance": [6, 5, 4]}},
    "meshes": {"shapes": {"file": ")" + file + R"("},
               "small": {"file": ")" + file + R"(", "transform": {"scale": [0.3, 0.3, 0.3],
                         "translate": [0, 1.6, 0]}}},
    "objects": [
      {"type": "quad", "origin": [-2, 0, -2], "u": [0, 0, 4], "v": [4, 0, 0], "material": "white"},
      {"type": "quad", "origin": [-0.3, 2.5, -0.3], "u": [0.6, 0, 0], "v": [0, 0, 0.6],
       "material": "lamp"})" + objects + "]}";
}

SceneDesc LoadInstancing(const std::string& json) {
  return LoadSceneFromString(json, "instancing-test.json", ".");
}

BvhBuildOptions Layout(BvhLayout layout) {
  BvhBuildOptions options;
  options.layout = layout;
  return options;
}

// Identity placements: each instanced triangle is the flattened one, so every ray meets the same
// surfaces with the same numbers, and the lights come in the same order.
TEST(Instancing, IdentityPlacementsRenderBitForBitAsTheFlattenedScene) {
  std::string objects = R"(,
      {"type": "instance", "mesh": "shapes"},
      {"type": "instance", "mesh": "small", "material": "lamp"})";
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    SceneDesc desc = LoadInstancing(InstancedScene(objects));
    ASSERT_EQ(desc.meshes.size(), 2u);
    ASSERT_EQ(desc.instances.size(), 2u);
    Scene instanced = BuildScene(desc, Layout(layout));
    Scene flat = BuildScene(FlattenInstances(desc), Layout(layout));
    ASSERT_TRUE(instanced.HasInstances());
    ASSERT_FALSE(flat.HasInstances());
    EXPECT_EQ(instanced.PlacedTriangleCount(), flat.TriangleCount());
    ASSERT_EQ(instanced.lights.size(), flat.lights.size());
    RenderResult a = RenderOnCpu(instanced), b = RenderOnCpu(flat);
    EXPECT_TRUE(BitIdentical(a.image.rgb, b.image.rgb)) << BvhLayoutName(layout);
    EXPECT_EQ(a.stats.nonfiniteSamples, 0u);
  }
}


// Failing 8x8 blocks (Welch's t at the 1% level) between two renderers over kSeeds seeds each,
// and the count a Binomial(blocks, 0.01) exceeds with probability 1e-3.
template <typename RenderA, typename RenderB>
void ExpectBlocksAgree(RenderA renderA, RenderB renderB, const std::string& what) {
  const int kSeeds = 6;
  const double kBlockAlpha = 0.01;
  std::vector<std::vector<double>> a, b;  // [seed][block]
  for (int k = 0; k < kSeeds; ++k) {
    a.push_back(BlockLuminance(renderA(100 + k)));
    b.push_back(BlockLuminance(renderB(200 + k)));
  }
  int blocks = int(a[0].size()), failing = FailingBlocks(a, b, kBlockAlpha);
  EXPECT_LE(failing, BinomialUpperBound(blocks, kBlockAlpha, 1e-3))
      << what << ": " << failing << " of " << blocks << " blocks differ at the 1% level";
}

// Rotation, non-uniform scale and mirroring, an emissive override on a scaled (and mirrored)
// placement: the float transforms round differently from the flattened triangles, so the
// images agree in distribution, block by block. The emissive instances test the lights' power
// (area in world space) and sampling pdf.
const char* kGeneralPlacements = R"(,
    {"type": "instance", "mesh": "shapes", "transform": {"rotate": [0, 35, 10],
     "translate": [-0.4, 0.2, 0]}},
    {"type": "instance", "mesh": "shapes", "material": "red", "transform": {
     "scale": [0.6, 1.3, 0.8], "translate": [0.7, 0.1, -0.5]}},
    {"type": "instance", "mesh": "shapes", "transform": {"scale": [-0.7, 0.7, 0.7],
     "rotate": [20, 0, 0], "translate": [0.3, 0.6, 0.6]}},
    {"type": "instance", "mesh": "small", "material": "lamp", "transform": {
     "scale": [1.5, 0.5, 2.0], "translate": [-0.6, 0.4, 0]}},
    {"type": "instance", "mesh": "small", "material": "lamp", "transform": {
     "scale": [1, -1, 1], "translate": [0.8, 2.8, 0]}})";

TEST(Instancing, GeneralTransformsAgreeWithTheFlattenedSceneBlockByBlock) {
  auto render = [](bool flatten) {
    return [flatten](int seed) {
      SceneDesc desc = LoadInstancing(InstancedScene(kGeneralPlacements, 48, 8, seed));
      if (flatten) desc = FlattenInstances(std::move(desc));
      RenderResult r = RenderOnCpu(BuildScene(std::move(desc)));
      EXPECT_EQ(r.stats.nonfiniteSamples, 0u);
      return r.image;
    };
  };
  ExpectBlocksAgree(render(false), render(true), "instanced vs flattened");
}

// The two levels against a brute-force loop over every instance and every triangle of its
// mesh, in object space (the same arithmetic: the hit distance must match exactly), and against
// the flattened scene's world-space triangles (a few ulps apart: the transform rounds).
TEST(Instancing, TwoLevelHitsMatchBruteForceInObjectAndWorldSpace) {
  SceneDesc desc = LoadInstancing(InstancedScene(kGeneralPlacements));
  Scene flat = BuildScene(FlattenInstances(desc));
  SceneView flatView = HostSceneView(flat);
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    Scene scene = BuildScene(desc, Layout(layout));
    SceneView view = HostSceneView(scene);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 1500; ++i) {
      Ray ray{vec3(2.0f * u(rng), 1.0f + u(rng), 2.5f), glm::normalize(vec3(u(rng), u(rng), -1.5f))};
      HitRecord bvh;
      bool found = IntersectClosest(view, ray, kInfinity, &bvh, nullptr);
      float best = kInfinity;
      for (uint32_t id = 0; id < scene.instances.size(); ++id) {
        const Instance& inst = scene.instances[id];
        float dt = 0.0f;
        Ray r = (inst.flags & kInstanceIdentity) ? ray : ObjectRay(inst, ray, &dt);
        uint32_t count = scene.meshBvhs[inst.mesh].primCount;
        for (uint32_t p = inst.primOffset; p < inst.primOffset + count; ++p) {
          float t;
          vec2 uv;
          if (IntersectPrim(view, p, r, best - dt, &t, &uv)) best = t + dt;
        }
      }
      ASSERT_EQ(found, best < kInfinity) << "ray " << i << " " << BvhLayoutName(layout);
      if (!found) continue;
      ++hits;
      EXPECT_EQ(bvh.t, best) << "ray " << i;
      HitRecord world;
      ASSERT_TRUE(IntersectClosest(flatView, ray, kInfinity, &world, nullptr)) << "ray " << i;
      EXPECT_NEAR(world.t, bvh.t, 1e-4f * bvh.t) << "ray " << i;
      EXPECT_EQ(IntersectAny(view, ray, bvh.t * 1.001f, nullptr), true);
      EXPECT_EQ(IntersectAny(view, ray, bvh.t * 0.999f, nullptr), false);
    }
    EXPECT_GT(hits, 250);
  }
}

// 300 overlapping placements in a 6x5x10 block: a top level several wide nodes deep, with many
// instances a node, where the one-loop walks leave an instance for the next one of a node or
// leaf and for the node's children. Both layouts must find the same nearest hit (t, instance,
// primitive), and the occlusion query must agree with it, for rays from inside and outside the
// block; with the top level's leaves of one instance (the default) and of up to four.
TEST(Instancing, ManyOverlappingInstancesGiveTheSameHitsInBothLayouts) {
  std::string objects;
  std::mt19937 placeRng(3);
  std::uniform_real_distribution<float> angle(0.0f, 180.0f), scale(0.6f, 1.4f);
  for (int i = 0; i < 300; ++i) {
    const float x = -1.5f + 0.6f * float(i % 6), y = 0.2f + 0.5f * float(i / 6 % 5),
                z = -2.0f + 0.4f * float(i / 30);
    objects += R"(, {"type": "instance", "mesh": "small", "transform": {"scale": [)" +
               std::to_string(scale(placeRng)) + ", " + std::to_string(scale(placeRng)) +
               ", 1], \"rotate\": [0, " + std::to_string(angle(placeRng)) +
               R"(, 0], "translate": [)" + std::to_string(x) + ", " + std::to_string(y - 1.6f) +
               ", " + std::to_string(z) + "]}}";
  }
  SceneDesc desc = LoadInstancing(InstancedScene(objects));
  for (int leafSize : {1, 4}) {
    BvhBuildOptions binaryOptions = Layout(BvhLayout::kBinary), wideOptions = Layout(BvhLayout::kWide);
    binaryOptions.topLevelLeafSize = wideOptions.topLevelLeafSize = leafSize;
    Scene binary = BuildScene(desc, binaryOptions);
    Scene wide = BuildScene(desc, wideOptions);
    uint32_t largestLeaf = 0;
    for (const BvhNode& n : binary.tlasNodes) largestLeaf = std::max(largestLeaf, n.IsLeaf() ? n.count : 0u);
    EXPECT_EQ(largestLeaf > 1u, leafSize > 1) << "top-level leaves of up to " << leafSize;
    SceneView bv = HostSceneView(binary), wv = HostSceneView(wide);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int hits = 0;
    for (int i = 0; i < 3000; ++i) {
      const vec3 o = i % 2 ? vec3(2.0f * u(rng), 1.2f + 1.2f * u(rng), 2.5f * u(rng))
                           : vec3(3.0f * u(rng), 1.2f + 2.0f * u(rng), 4.0f);
      const vec3 d = glm::normalize(i % 2 ? vec3(u(rng), u(rng), u(rng))
                                          : vec3(0.5f * u(rng), 0.5f * u(rng), -1.0f));
      const Ray ray{o, d};
      HitRecord a, b;
      const bool foundA = IntersectClosest(bv, ray, kInfinity, &a, nullptr);
      const bool foundB = IntersectClosest(wv, ray, kInfinity, &b, nullptr);
      ASSERT_EQ(foundA, foundB) << "ray " << i << ", leaves of " << leafSize;
      EXPECT_EQ(IntersectAny(bv, ray, kInfinity, nullptr), foundA) << "ray " << i;
      EXPECT_EQ(IntersectAny(wv, ray, kInfinity, nullptr), foundB) << "ray " << i;
      if (!foundA) continue;
      ++hits;
      ASSERT_EQ(a.t, b.t) << "ray " << i << ", leaves of " << leafSize;
      EXPECT_EQ(a.instance, b.instance) << "ray " << i;
      EXPECT_EQ(binary.prims[a.prim].tagIndex, wide.prims[b.prim].tagIndex) << "ray " << i;
      for (const SceneView* v : {&bv, &wv}) {
        EXPECT_TRUE(IntersectAny(*v, ray, b.t * 1.001f, nullptr)) << "ray " << i;
        EXPECT_FALSE(IntersectAny(*v, ray, b.t * 0.999f, nullptr)) << "ray " << i;
      }
    }
    EXPECT_GT(hits, 1000);
    // Rays with a NaN or infinite component find nothing and stop (the walks never start).
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
    for (const Ray& bad : {Ray{vec3(nan, 1.0f, 4.0f), vec3(0.0f, 0.0f, -1.0f)},
                           Ray{vec3(0.0f, 1.0f, 4.0f), vec3(0.0f, nan, -1.0f)},
                           Ray{vec3(0.0f, 1.0f, inf), vec3(0.0f, 0.0f, -1.0f)}}) {
      for (const SceneView* v : {&bv, &wv}) {
        HitRecord h;
        EXPECT_FALSE(IntersectClosest(*v, bad, kInfinity, &h, nullptr));
        EXPECT_FALSE(IntersectAny(*v, bad, kInfinity, nullptr));
      }
    }
  }
}

// What a fresh build and a moved-then-rebuilt scene must share: the top level, the instance
// table and the light distribution (scaling an emissive instance changes its lights' power).
void ExpectSameTopLevel(const Scene& a, const Scene& b) {
  EXPECT_TRUE(BitIdentical(a.instances, b.instances));
  EXPECT_EQ(a.instanceOrder, b.instanceOrder);
  EXPECT_TRUE(BitIdentical(a.tlasNodes, b.tlasNodes));
  EXPECT_TRUE(BitIdentical(a.tlasWideNodes, b.tlasWideNodes));
  EXPECT_EQ(a.lightPmf, b.lightPmf);
  EXPECT_EQ(a.lightCdf, b.lightCdf);
  EXPECT_EQ(a.sceneCenter, b.sceneCenter);
  EXPECT_EQ(a.sceneRadius, b.sceneRadius);
}

TEST(Instancing, MovingAnInstanceAndRebuildingTheTopLevelEqualsAFreshBuild) {
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    SceneDesc desc = LoadInstancing(InstancedScene(kGeneralPlacements, 32, 4));
    Scene moved = BuildScene(desc, Layout(layout));
    size_t nodesBefore = moved.NodeCount();
    std::vector<PrimRef> primsBefore = moved.prims;
    glm::dmat4 to = glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, 0.1, -0.3)) *
                    glm::scale(glm::dmat4(1.0), glm::dvec3(2.0, 1.0, 0.5));
    glm::dmat4 lamp = glm::translate(glm::dmat4(1.0), glm::dvec3(-0.5, 0.3, 0.1)) *
                      glm::scale(glm::dmat4(1.0), glm::dvec3(3.0, 1.0, 1.0));
    UpdateInstanceTransform(moved, 1, to);
    UpdateInstanceTransform(moved, 3, lamp);
    RebuildTopLevel(moved);
    EXPECT_EQ(moved.NodeCount(), nodesBefore);  // bottom levels untouched
    EXPECT_EQ(0, std::memcmp(moved.prims.data(), primsBefore.data(),
                             primsBefore.size() * sizeof(PrimRef)));
    desc.instances[1].toWorld = to;
    desc.instances[3].toWorld = lamp;
    Scene fresh = BuildScene(desc, Layout(layout));
    ExpectSameTopLevel(moved, fresh);
    EXPECT_TRUE(BitIdentical(RenderOnCpu(moved).image.rgb, RenderOnCpu(fresh).image.rgb))
        << BvhLayoutName(layout);
  }
}

// A live session (what the preview server holds): the scene's top level rebuilt after a move,
// TopLevelChanged re-reads only that; the next film is the fresh moved scene's, bit for bit.
TEST(Instancing, ASessionSeesTheMovedInstancesAfterTopLevelChanged) {
  SceneDesc desc = LoadInstancing(InstancedScene(kGeneralPlacements, 32, 4));
  Scene scene = BuildScene(desc);
  RenderOptions options;
  options.threads = 2;
  auto session = MakeCpuSession(scene, options);
  FilmImage before = session->Render().image;
  glm::dmat4 to = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.8, 0.2));
  UpdateInstanceTransform(scene, 3, to);  // an emissive one: the light choice changes too
  RebuildTopLevel(scene);
  session->TopLevelChanged();
  session->ResetFilm();
  FilmImage after = session->Render().image;
  desc.instances[3].toWorld = to;
  EXPECT_TRUE(BitIdentical(after.rgb, RenderOnCpu(BuildScene(desc)).image.rgb));
  EXPECT_FALSE(BitIdentical(after.rgb, before.rgb));
}

TEST(Instancing, BadMovesAreRefused) {
  Scene scene = BuildScene(LoadInstancing(InstancedScene(kGeneralPlacements, 16, 1)));
  EXPECT_THROW(UpdateInstanceTransform(scene, 99, glm::dmat4(1.0)), std::invalid_argument);
  EXPECT_THROW(UpdateInstanceTransform(scene, 0, glm::dmat4(0.0)), std::invalid_argument);
  glm::dmat4 projective(1.0);
  projective[0][3] = 0.5;  // the last row is no longer 0 0 0 1
  EXPECT_THROW(UpdateInstanceTransform(scene, 0, projective), std::invalid_argument);
  glm::dmat4 nan(1.0);
  nan[3][0] = std::nan("");
  EXPECT_THROW(UpdateInstanceTransform(scene, 0, nan), std::invalid_argument);
}

// An emissive placement's lights carry its world-space area: scaled by 2 in every direction it
// emits 4 times the power, by (1, 3, 1) a power between 1 and 3 times (areas of faces that are
// not perpendicular to y grow by up to 3).
TEST(Instancing, EmissiveInstancesEmitByTheirWorldArea) {
  auto instancePower = [](const std::string& transform) {
    Scene scene = BuildScene(LoadInstancing(InstancedScene(
        R"(, {"type": "instance", "mesh": "small", "material": "lamp", "transform": )" +
            transform + "}", 16, 1)));
    double power = 0.0;
    for (size_t i = 0; i < scene.lights.size(); ++i)
      if (scene.lights[i].instance >= 0) power += scene.lightPower[i];
    return power;
  };
  double one = instancePower(R"({"scale": [1, 1, 1]})");
  ASSERT_GT(one, 0.0);
  EXPECT_NEAR(instancePower(R"({"scale": [2, 2, 2], "rotate": [0, 40, 0]})") / one, 4.0, 1e-5);
  EXPECT_NEAR(instancePower(R"({"scale": [-2, 2, 2]})") / one, 4.0, 1e-5);
  double stretched = instancePower(R"({"scale": [1, 3, 1]})") / one;
  EXPECT_GT(stretched, 1.2);
  EXPECT_LT(stretched, 3.0);
}

// Flat scenes pay nothing: no instance table, no top level, the single-level query.
TEST(Instancing, FlatScenesHaveNoTopLevel) {
  Scene scene = BuildScene(LoadInstancing(InstancedScene("", 16, 1)));
  EXPECT_FALSE(scene.HasInstances());
  EXPECT_TRUE(scene.tlasNodes.empty());
  EXPECT_TRUE(scene.tlasWideNodes.empty());
  EXPECT_EQ(HostSceneView(scene).instanceCount, 0u);
}

}  // namespace
}  // namespace pt::test
