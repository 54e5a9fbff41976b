// No direction is special (issue 28): rays along the axes, with +0, -0, denormal, tiny and huge
// components and near-axis ones, from origins on node planes, on the grid lines of tessellated
// floors and walls and inside node boxes, through every layout and walk (binary, wide in the
// octant order and nearest-first, flat and instanced; closest and any hit). Each must find brute
// force's hit, and must cull as well as for a slightly perturbed direction: the nodes it visits
// stay within 1.5x of those the perturbed rays visit. (Before the parallel-axis test of
// wide_node_test.h a ray along an axis culled the wide tree by one axis only: 20-200x the nodes.)
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "src/geometry/instance.h"
#include "src/geometry/traverse.h"
#include "tests/brute_force.h"
#include "tests/hard_geometry_util.h"

namespace pt {
namespace {

constexpr float kCell = 0.25f;

// Triangles of a grid of square cells in the plane where axis `normal` is `at`, spanning
// [-half, half] on the two other axes.
void AddGrid(std::vector<Triangle>* tris, int normal, float at, float half) {
  const int cells = int(2.0f * half / kCell);
  auto point = [&](int i, int j) {
    vec3 p(at);
    p[(normal + 1) % 3] = -half + kCell * float(i);
    p[(normal + 2) % 3] = -half + kCell * float(j);
    return p;
  };
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; j < cells; ++j) {
      tris->push_back({point(i, j), point(i + 1, j), point(i + 1, j + 1)});
      tris->push_back({point(i, j), point(i + 1, j + 1), point(i, j + 1)});
    }
  }
}

// The 12 triangles of the box [lo, hi].
void AddBox(std::vector<Triangle>* tris, vec3 lo, vec3 hi) {
  auto corner = [&](int k) {
    return vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  };
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    tris->push_back({corner(f[0]), corner(f[1]), corner(f[2])});
    tris->push_back({corner(f[0]), corner(f[2]), corner(f[3])});
  }
}

// A floor and a wall tessellated on the kCell grid, boxes on it, a soup of small triangles,
// axis-aligned quads and a few spheres: planes shared by many nodes on every axis.
struct AxisScene {
  std::vector<Triangle> tris;
  std::vector<Quad> quads;
  std::vector<Sphere> spheres;
};

AxisScene MakeAxisScene() {
  AxisScene s;
  AddGrid(&s.tris, 1, 0.0f, 2.0f);   // floor y = 0
  AddGrid(&s.tris, 0, 1.5f, 1.0f);   // wall x = 1.5
  for (int i = 0; i < 6; ++i) {
    const vec3 lo(-1.75f + 0.5f * float(i), 0.0f, -1.0f + kCell * float(i % 3));
    AddBox(&s.tris, lo, lo + vec3(kCell, 0.25f + kCell * float(i), 2.0f * kCell));
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f), small(-0.06f, 0.06f);
  for (int i = 0; i < 500; ++i) {
    const vec3 c(u(rng), 1.0f + 0.5f * u(rng), u(rng));
    s.tris.push_back({c, c + vec3(small(rng), small(rng), small(rng)),
                      c + vec3(small(rng), small(rng), small(rng))});
  }
  s.quads.push_back({vec3(-1.0f, 1.25f, -1.0f), vec3(0.5f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 0.5f)});
  s.quads.push_back({vec3(0.5f, 0.5f, -2.0f), vec3(0.0f, 0.5f, 0.0f), vec3(0.5f, 0.0f, 0.0f)});
  s.spheres.push_back({vec3(-0.5f, 0.75f, 0.5f), 0.25f});
  s.spheres.push_back({vec3(0.75f, 1.5f, -0.75f), 0.125f});
  return s;
}

// Directions along each axis with the other components set to `other` (each of the six axis
// directions, both signs), scaled by `scale`.
struct DirectionFamily {
  const char* name;
  float a, b;        // the two other components (before scaling)
  float scale;       // of the whole direction (huge: 1e30)
  bool perturbable;  // false: already off-axis (near-axis families)
};

const DirectionFamily kFamilies[] = {
    {"zeros", 0.0f, 0.0f, 1.0f, true},
    {"negative zeros", -0.0f, -0.0f, 1.0f, true},
    {"mixed zeros", -0.0f, 0.0f, 1.0f, true},
    {"denormals", 1e-40f, -1e-45f, 1.0f, true},
    {"small normals", 1.5e-38f, -2e-38f, 1.0f, true},
    {"tiny", 1e-25f, -3e-22f, 1.0f, true},
    {"huge", 0.0f, -0.0f, 1e30f, true},
    {"huge, off axis", 1e-10f, 1.0f, 1e25f, true},
    {"near axis 1e-7", 1e-7f, -0.0f, 1.0f, false},
    {"near axis 1e-4", 1e-4f, 2e-4f, 1.0f, false},
};

vec3 FamilyDirection(const DirectionFamily& f, int axis, bool negative) {
  vec3 d(0.0f);
  d[axis] = negative ? -1.0f : 1.0f;
  d[(axis + 1) % 3] = f.a;
  d[(axis + 2) % 3] = f.b;
  return d * f.scale;
}

// The planes (axis, coordinate) of flat axis-aligned primitives: a floor, a wall, a box's face.
// A ray lying in one touches every box along it that the flat primitives there have, in exact
// arithmetic, and visits them in any conservative walk, while a perturbed ray leaves the
// plane at once: such rays are checked against brute force but not counted (InPlane).
using FlatPlanes = std::set<std::pair<int, float>>;

void AddFlatPlanes(FlatPlanes* planes, const vec3* corners, int count) {
  for (int a = 0; a < 3; ++a) {
    bool flat = true;
    for (int k = 1; k < count; ++k) flat = flat && corners[k][a] == corners[0][a];
    if (flat) planes->insert({a, corners[0][a]});
  }
}

bool InPlane(const FlatPlanes& planes, vec3 o, int axis) {
  for (int k = 1; k <= 2; ++k) {
    const int a = (axis + k) % 3;
    if (planes.count({a, o[a]})) return true;
  }
  return false;
}

// Origins for rays along `axis`: the two other coordinates on node planes (the bounds of nodes
// of the binary tree `nodes`), on the grid, or inside a node's box; along the axis, inside a
// node's box or outside the scene. Every other origin is kept off the planes of flat
// primitives (those rays are the ones counted).
std::vector<vec3> MakeOrigins(const std::vector<BvhNode>& nodes, const FlatPlanes& planes,
                              int axis, int count, std::mt19937& rng) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::vector<vec3> origins;
  for (int i = 0; i < count; ++i) {
    vec3 o;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const BvhNode& n = nodes[rng() % nodes.size()];
      for (int k = 0; k < 3; ++k)
        o[k] = n.boundsMin[k] + u01(rng) * (n.boundsMax[k] - n.boundsMin[k]);
      for (int k = 1; k <= 2; ++k) {
        const int a = (axis + k) % 3;
        switch ((i / 2 + k) % 4) {
          case 0: o[a] = n.boundsMin[a]; break;
          case 1: o[a] = n.boundsMax[a]; break;
          case 2: o[a] = kCell * std::round(o[a] / kCell); break;  // a grid line
          default: break;                                            // inside the box
        }
      }
      if (i % 2 == 0 || !InPlane(planes, o, axis)) break;
    }
    if (i % 3 == 0) o[axis] = i % 2 ? -3.0f : 3.0f;
    origins.push_back(o);
  }
  return origins;
}

// A direction turned by about 1e-5 off every axis: what the nodes visited are compared with.
vec3 Perturbed(vec3 d) {
  const float largest = std::max(std::fabs(d.x), std::max(std::fabs(d.y), std::fabs(d.z)));
  return glm::normalize(glm::normalize(d / largest) + 1e-5f * vec3(0.83f, -0.61f, 0.37f));
}

struct WalkCounts {
  uint64_t axis = 0, perturbed = 0;
};

BvhBuildOptions AxisOptions(BvhLayout layout, BvhBuilder builder) {
  BvhBuildOptions o;
  o.layout = layout;
  o.builder = builder;
  o.threads = 2;
  return o;
}

// The closest hit of `view` by each walk of its layout, against brute force; accumulates the
// nodes each walk visited.
void CheckRay(const SceneView& view, const Ray& ray, float tMax, const char* what,
              WalkCounts* counts, bool axisRay) {
  HitRecord brute;
  const bool hit = test::BruteForceClosest(view, ray, tMax, &brute);
  TraversalCounters closest{}, any{}, nearest{};
  HitRecord h;
  ASSERT_EQ(IntersectClosest(view, ray, tMax, &h, &closest), hit) << what;
  if (hit) {
    ASSERT_EQ(h.t, brute.t) << what;
    ASSERT_EQ(view.prims[h.prim].tagIndex, view.prims[brute.prim].tagIndex) << what;
  }
  ASSERT_EQ(IntersectAny(view, ray, tMax, &any), hit) << what;
  if (view.bvhLayout == BvhLayout::kWide) {  // the GPU's nearest-first walk (scalar node test)
    PrimLeaf<TraceMode::kClosest> leaf(view, ray);
    float t = tMax;
    Traverse<TraceMode::kClosest, decltype(leaf), true>(SceneWideBvh(view), ray, &t, leaf,
                                                        &nearest);
    ASSERT_EQ(leaf.prim != HitRecord::kNoHit, hit) << what << " (nearest first)";
    if (hit) {
      ASSERT_EQ(t, brute.t) << what << " (nearest first)";
    }
  }
  const uint32_t nodes[3] = {closest.nodes, any.nodes, nearest.nodes};
  if (!counts) return;
  for (int w = 0; w < 3; ++w) (axisRay ? counts[w].axis : counts[w].perturbed) += nodes[w];
}

TEST(AxisRays, EveryLayoutAndWalkMatchesBruteForceAndCullsAsAPerturbedRay) {
  const AxisScene shapes = MakeAxisScene();
  const hard::ShapeScene binary = hard::BuildShapes(
      shapes.tris, shapes.quads, shapes.spheres, AxisOptions(BvhLayout::kBinary, BvhBuilder::kSah));
  const std::pair<BvhLayout, BvhBuilder> builds[] = {{BvhLayout::kBinary, BvhBuilder::kSah},
                                                     {BvhLayout::kWide, BvhBuilder::kSah},
                                                     {BvhLayout::kWide, BvhBuilder::kSbvh},
                                                     {BvhLayout::kWide, BvhBuilder::kLbvh}};
  FlatPlanes planes;
  for (const Triangle& t : shapes.tris) {
    const vec3 c[3] = {t.p0, t.p1, t.p2};
    AddFlatPlanes(&planes, c, 3);
  }
  for (const Quad& q : shapes.quads) {
    const vec3 c[4] = {q.origin, q.origin + q.u, q.origin + q.v, q.origin + q.u + q.v};
    AddFlatPlanes(&planes, c, 4);
  }
  for (const auto& [layout, builder] : builds) {
    const hard::ShapeScene scene = hard::BuildShapes(shapes.tris, shapes.quads, shapes.spheres,
                                                     AxisOptions(layout, builder));
    const std::string build = std::string(BvhLayoutName(layout)) + " " + BvhBuilderName(builder);
    for (const DirectionFamily& family : kFamilies) {
      WalkCounts counts[3];
      int compared = 0;
      std::mt19937 rng(13);
      for (int axis = 0; axis < 3; ++axis) {
        const std::vector<vec3> origins = MakeOrigins(binary.scene.nodes, planes, axis, 60, rng);
        for (size_t i = 0; i < origins.size(); ++i) {
          const vec3 d = FamilyDirection(family, axis, i % 2 == 1);
          const float tMax = i % 5 == 4 ? 1.0f / family.scale : kInfinity;
          const std::string what = build + ", " + family.name + ", axis " + std::to_string(axis) +
                                   ", ray " + std::to_string(i);
          WalkCounts* count = InPlane(planes, origins[i], axis) ? nullptr : counts;
          compared += count != nullptr;
          CheckRay(scene.view, Ray{origins[i], d}, tMax, what.c_str(), count, true);
          if (HasFatalFailure()) return;
          const Ray perturbed{origins[i], Perturbed(d)};
          CheckRay(scene.view, perturbed, tMax * family.scale, (what + " perturbed").c_str(),
                   count, false);
          if (HasFatalFailure()) return;
        }
      }
      EXPECT_GT(compared, 3 * 60 / 3) << build << ", " << family.name << ": rays counted";
      if (!family.perturbable) continue;
      const char* walks[3] = {"closest", "any", "nearest first"};
      for (int w = 0; w < 3; ++w) {
        if (counts[w].perturbed == 0) continue;
        const double ratio = double(counts[w].axis) / double(counts[w].perturbed);
        EXPECT_LE(ratio, 1.5) << build << ", " << family.name << ", " << walks[w] << ": "
                              << counts[w].axis << " nodes against " << counts[w].perturbed;
      }
    }
  }
}


// ---- Two levels ----

// The floor in world space and a mesh of boxes, a grid and a soup placed four times: as it is,
// moved along the grid, turned by 90 degrees about y and halved (exact transforms, so the
// object-space rays of axis rays are axis rays too).
Scene MakeInstancedAxisScene(BvhLayout layout) {
  SceneDesc d;
  d.render.width = d.render.height = 1;
  d.render.spp = 1;
  Material m;
  m.albedo = vec3(0.5f);
  d.materials.push_back(m);
  d.materialNames.push_back("m");
  AddGrid(&d.triangles, 1, 0.0f, 2.0f);
  const uint32_t world = uint32_t(d.triangles.size());
  for (int i = 0; i < 4; ++i) {
    const vec3 lo(-0.5f + kCell * float(i), 0.0f, -0.25f * float(i % 2));
    AddBox(&d.triangles, lo, lo + vec3(kCell, 0.25f * float(i + 1), kCell));
  }
  AddGrid(&d.triangles, 2, 0.5f, 0.5f);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), small(-0.05f, 0.05f);
  for (int i = 0; i < 200; ++i) {  // not flat: node planes off the flat primitives' planes
    const vec3 c(u(rng), 0.6f + 0.5f * u(rng), u(rng));
    d.triangles.push_back({c, c + vec3(small(rng), small(rng), small(rng)),
                           c + vec3(small(rng), small(rng), small(rng))});
  }
  d.meshes.push_back(MeshDesc{"boxes", world, uint32_t(d.triangles.size()) - world});
  const glm::dmat4 id(1.0);
  const glm::dmat4 turn(0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, -1, 0, 1, 1);  // columns
  const glm::dmat4 placements[] = {
      id, glm::translate(id, glm::dvec3(0.5, 0.25, -0.75)), turn,
      glm::scale(glm::translate(id, glm::dvec3(1, 1, 1)), glm::dvec3(0.5))};
  for (const glm::dmat4& toWorld : placements) d.instances.push_back(InstanceDesc{0, toWorld, -1});
  d.triangleNormals.resize(d.triangles.size());
  d.triangleMaterials.assign(d.triangles.size(), 0);
  BvhBuildOptions o = AxisOptions(layout, BvhBuilder::kSah);
  return BuildScene(std::move(d), o);
}

// The nearest hit over every instance by brute force, ties to the smaller (instance, tag) as
// the two-level walks take them (traverse_instanced.h).
bool BruteForceInstanced(const Scene& scene, const SceneView& view, const Ray& ray, float tMax,
                         float* tHit, uint32_t* instance, uint32_t* tag) {
  bool found = false;
  float best = tMax;
  for (uint32_t id = 0; id < scene.instances.size(); ++id) {
    const Instance& inst = scene.instances[id];
    float dt = 0.0f;
    const Ray r = (inst.flags & kInstanceIdentity) ? ray : ObjectRay(inst, ray, &dt);
    if (!TraceableRay(r)) continue;
    float local = best - dt;  // as InstanceLevel: the instance's limit, lowered by its hits
    bool hitHere = false;
    const uint32_t count = scene.meshBvhs[inst.mesh].primCount;
    for (uint32_t p = inst.primOffset; p < inst.primOffset + count; ++p) {
      float t;
      vec2 uv;
      if (!IntersectPrim(view, p, r, found ? NextFloatUp(local) : local, &t, &uv)) continue;
      const uint32_t pTag = view.prims[p].tagIndex;
      if (found && !(t < local) && !(id < *instance || (id == *instance && pTag < *tag))) continue;
      local = t;
      *instance = id;
      *tag = pTag;
      found = hitHere = true;
    }
    if (hitHere) best = std::fmin(local + dt, best);
  }
  *tHit = best;
  return found;
}

TEST(AxisRays, TwoLevelWalksMatchBruteForceAndCullAsAPerturbedRay) {
  const Scene binaryRef = MakeInstancedAxisScene(BvhLayout::kBinary);
  FlatPlanes planes;  // of the placed triangles (the placements are exact in float)
  const SceneDesc& desc = binaryRef.desc;
  auto addPlanes = [&](const Triangle& t, const glm::dmat4& toWorld) {
    vec3 c[3] = {t.p0, t.p1, t.p2};
    for (vec3& p : c) p = vec3(toWorld * glm::dvec4(glm::dvec3(p), 1.0));
    AddFlatPlanes(&planes, c, 3);
  };
  for (uint32_t i = 0; i < desc.meshes[0].firstTriangle; ++i)
    addPlanes(desc.triangles[i], glm::dmat4(1.0));
  for (const InstanceDesc& inst : desc.instances) {
    const MeshDesc& m = desc.meshes[inst.mesh];
    for (uint32_t i = m.firstTriangle; i < m.firstTriangle + m.triangleCount; ++i)
      addPlanes(desc.triangles[i], inst.toWorld);
  }
  for (BvhLayout layout : {BvhLayout::kBinary, BvhLayout::kWide}) {
    const Scene scene = MakeInstancedAxisScene(layout);
    const SceneView view = HostSceneView(scene);
    for (const DirectionFamily& family : kFamilies) {
      WalkCounts counts[2];
      int compared = 0;
      std::mt19937 rng(17);
      for (int axis = 0; axis < 3; ++axis) {
        const std::vector<vec3> origins = MakeOrigins(binaryRef.nodes, planes, axis, 40, rng);
        for (size_t i = 0; i < origins.size(); ++i) {
          const vec3 d = FamilyDirection(family, axis, i % 2 == 1);
          for (bool axisRay : {true, false}) {
            const Ray ray{origins[i], axisRay ? d : Perturbed(d)};
            const float tMax = kInfinity;
            float t = 0.0f;
            uint32_t instance = 0, tag = 0;
            const bool hit = BruteForceInstanced(scene, view, ray, tMax, &t, &instance, &tag);
            SCOPED_TRACE(std::string(BvhLayoutName(layout)) + ", " + family.name + ", axis " +
                         std::to_string(axis) + ", ray " + std::to_string(i) +
                         (axisRay ? "" : " perturbed"));
            TraversalCounters closest{}, any{};
            HitRecord h;
            ASSERT_EQ(IntersectClosest(view, ray, tMax, &h, &closest), hit);
            if (hit) {
              ASSERT_EQ(h.t, t);
              ASSERT_EQ(h.instance, instance);
              ASSERT_EQ(view.prims[h.prim].tagIndex, tag);
            }
            ASSERT_EQ(IntersectAny(view, ray, tMax, &any), hit);
            if (InPlane(planes, origins[i], axis)) continue;
            compared += axisRay;
            (axisRay ? counts[0].axis : counts[0].perturbed) += closest.nodes;
            (axisRay ? counts[1].axis : counts[1].perturbed) += any.nodes;
          }
        }
      }
      EXPECT_GT(compared, 3 * 40 / 3) << family.name << ": rays counted";
      if (!family.perturbable) continue;
      for (int w = 0; w < 2; ++w) {
        EXPECT_LE(double(counts[w].axis), 1.5 * double(counts[w].perturbed))
            << BvhLayoutName(layout) << ", " << family.name << (w ? ", any" : ", closest") << ": "
            << counts[w].axis << " nodes against " << counts[w].perturbed;
      }
    }
  }
}

}  // namespace
}  // namespace pt
