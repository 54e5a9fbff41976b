// MeshSink::AddIndexed (an indexed primitive: each vertex transformed once, a big one's
// triangles on every core) against Add of each triangle in order: the same triangles, values and
// skipped ones, bit for bit, over transforms that mirror, scale hugely or tinily, and attribute
// sets that start, stop and backfill the optional arrays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "src/core/prefault.h"
#include "src/io/mesh_common.h"

namespace pt {
namespace {

// A pool of random vertices with every attribute (some normals zero, some second UVs NaN, one
// in fifty positions infinite) and `count` triangles over it: about one in twenty degenerate (a
// repeated index, or three collinear vertices the pool holds on purpose).
struct RandomMesh {
  IndexedVertices v;
  std::vector<uint32_t> indices;
};

RandomMesh MakeRandomMesh(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto v3 = [&] { return vec3(u(rng), u(rng), u(rng)); };
  RandomMesh m;
  size_t vertices = count / 2 + 3;
  for (size_t i = 0; i < vertices; ++i) {
    vec3 p = v3();
    if (i % 3 == 2) p = 2.0f * m.v.positions[i - 1] - m.v.positions[i - 2];  // collinear triples
    if (rng() % 50 == 0) p.y = std::numeric_limits<float>::infinity();
    m.v.positions.push_back(p);
    m.v.normals.push_back(rng() % 40 == 0 ? vec3(0.0f) : v3());
    m.v.uvs.push_back(vec2(u(rng), u(rng)));
    m.v.uvs1.push_back(vec2(u(rng), rng() % 2 ? std::nanf("") : u(rng)));
    m.v.tangents.push_back(vec4(v3(), u(rng)));
    m.v.colors.push_back(vec4(v3(), 1.0f));
  }
  std::uniform_int_distribution<uint32_t> pick(0, uint32_t(vertices - 1));
  for (size_t t = 0; t < count; ++t) {
    uint32_t i[3] = {pick(rng), pick(rng), pick(rng)};
    switch (rng() % 40) {
      case 0: i[2] = i[0]; break;  // repeated vertex
      case 1:  // a collinear triple
        i[0] = std::min<uint32_t>(i[0], uint32_t(vertices - 3)) / 3 * 3;
        i[1] = i[0] + 1, i[2] = i[0] + 2;
        break;
      default: break;
    }
    m.indices.insert(m.indices.end(), {i[0], i[1], i[2]});
  }
  return m;
}

// The mesh with only the attributes `has` names.
IndexedVertices Only(const IndexedVertices& all, const VertexPresence& has) {
  IndexedVertices v;
  v.positions = all.positions;
  if (has.normals) v.normals = all.normals;
  if (has.uvs) v.uvs = all.uvs;
  if (has.uvs1) v.uvs1 = all.uvs1;
  if (has.tangents) v.tangents = all.tangents;
  if (has.colors) v.colors = all.colors;
  return v;
}

template <typename T>
void ExpectSameBits(const std::vector<T>& a, const std::vector<T>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  if (a.empty()) return;
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(T))) << what;
}

void ExpectSameScene(const SceneDesc& a, const SceneDesc& b) {
  EXPECT_EQ(a.skippedDegenerateTriangles, b.skippedDegenerateTriangles);
  ExpectSameBits(a.triangles, b.triangles, "triangles");
  ExpectSameBits(a.triangleNormals, b.triangleNormals, "normals");
  ExpectSameBits(a.triangleMaterials, b.triangleMaterials, "materials");
  ExpectSameBits(a.triangleUvs, b.triangleUvs, "uvs");
  ExpectSameBits(a.triangleUvs1, b.triangleUvs1, "uvs1");
  ExpectSameBits(a.triangleTangents, b.triangleTangents, "tangents");
  ExpectSameBits(a.triangleColors, b.triangleColors, "colors");
}

// Adds the triangles [first, last) of m with attributes `has` one by one into `inOrder` and as
// one indexed primitive into `indexed`.
void AddBoth(MeshSink& inOrder, MeshSink& indexed, const RandomMesh& m, size_t first, size_t last,
             const VertexPresence& has, uint32_t material) {
  IndexedVertices v = Only(m.v, has);
  for (size_t t = first; t < last; ++t) {
    vec3 p[3], n[3];
    vec2 uv[3], uv1[3];
    vec4 tangent[3], color[3];
    for (int k = 0; k < 3; ++k) {
      uint32_t i = m.indices[3 * t + size_t(k)];
      p[k] = v.positions[i];
      if (has.normals) n[k] = v.normals[i];
      if (has.uvs) uv[k] = v.uvs[i];
      if (has.uvs1) uv1[k] = v.uvs1[i];
      if (has.tangents) tangent[k] = v.tangents[i];
      if (has.colors) color[k] = v.colors[i];
    }
    VertexAttributes a;
    a.normals = has.normals ? n : nullptr;
    a.uvs = has.uvs ? uv : nullptr;
    a.uvs1 = has.uvs1 ? uv1 : nullptr;
    a.tangents = has.tangents ? tangent : nullptr;
    a.colors = has.colors ? color : nullptr;
    inOrder.Add(p, a, material);
  }
  std::vector<uint32_t> indices(m.indices.begin() + ptrdiff_t(3 * first),
                                m.indices.begin() + ptrdiff_t(3 * last));
  indexed.AddIndexed(v, indices, material);
}

glm::dmat4 Transform(int which) {
  glm::dmat4 m(1.0);
  switch (which) {
    case 1: m = glm::scale(m, glm::dvec3(-1.0, 1.0, 1.0)); break;  // mirrors
    case 2: m = glm::scale(glm::translate(m, glm::dvec3(1e6, 0, -3)), glm::dvec3(1e5)); break;
    case 3: m = glm::scale(glm::rotate(m, 0.7, glm::dvec3(1, 2, 3)), glm::dvec3(1e-6, 2e-6, -1e-6));
      break;
    default: break;
  }
  return m;
}

TEST(MeshIndexed, SameAsAddInOrderOverTransformsAndAttributeSets) {
  // Enough triangles that a primitive runs on several threads (2^12 per thread).
  constexpr size_t kCount = 100000;
  RandomMesh tris = MakeRandomMesh(kCount, 7);
  for (int which = 0; which < 4; ++which) {
    SCOPED_TRACE("transform " + std::to_string(which));
    SceneDesc a, b;
    MeshSink inOrder(a, Transform(which), -1, "in order");
    MeshSink batched(b, Transform(which), -1, "indexed");
    VertexPresence none, all{true, true, true, true, true}, some{true, false, true, false, false};
    // No optional data yet, then data that backfills, then none again (filled), then some.
    AddBoth(inOrder, batched, tris, 0, 1000, none, 3);
    AddBoth(inOrder, batched, tris, 1000, 60000, all, 4);
    AddBoth(inOrder, batched, tris, 60000, 60010, none, 5);
    AddBoth(inOrder, batched, tris, 60010, kCount, some, 6);
    AddBoth(inOrder, batched, tris, 0, 0, all, 7);  // an empty primitive adds nothing
    EXPECT_GT(a.skippedDegenerateTriangles, 0);
    EXPECT_EQ(a.triangleColors.size(), a.triangles.size());
    ExpectSameScene(a, b);
  }
}

TEST(MeshIndexed, MaterialOverrideSingleTriangleAndAllSkipped) {
  RandomMesh m;
  m.v.positions = {vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f)};
  m.v.normals = {vec3(0, 0, 1), vec3(0, 0, 1), vec3(0, 0, 1)};
  m.v.uvs = {vec2(0.0f), vec2(1.0f), vec2(2.0f)};
  m.indices = {0, 1, 2, 0, 1, 0, 2, 1, 0};  // the second degenerate: skipped by both
  SceneDesc a, b;
  MeshSink inOrder(a, glm::dmat4(1.0), 2, "in order"), indexed(b, glm::dmat4(1.0), 2, "indexed");
  AddBoth(inOrder, indexed, m, 1, 2, VertexPresence{true, true}, 9);  // every triangle skipped
  EXPECT_TRUE(b.triangleUvs.empty());  // no triangle kept: no UV array yet (Add's rule)
  AddBoth(inOrder, indexed, m, 0, 1, VertexPresence{}, 9);
  AddBoth(inOrder, indexed, m, 1, 3, VertexPresence{true}, 9);
  EXPECT_EQ(b.triangles.size(), 2u);
  EXPECT_EQ(b.skippedDegenerateTriangles, 2);
  EXPECT_EQ(b.triangleMaterials, (std::vector<uint32_t>{2, 2}));
  ExpectSameScene(a, b);
}

// Room reserved ahead (a scene placing one file again and again) changes no value: the
// primitive writes into capacity paged in by ReserveOnThreads.
TEST(MeshIndexed, ReservedArraysGiveTheSameScene) {
  constexpr size_t kCount = 70000;
  RandomMesh tris = MakeRandomMesh(kCount, 13);
  SceneDesc a, b;
  MeshSink inOrder(a, Transform(2), -1, "in order"), batched(b, Transform(2), -1, "indexed");
  VertexPresence all{true, true, true, true, true};
  AddBoth(inOrder, batched, tris, 0, 10, all, 1);
  ReserveTriangles(b, 3 * kCount);  // the optional arrays exist now: they are reserved too
  EXPECT_GE(b.triangles.capacity(), 3 * kCount);
  EXPECT_GE(b.triangleTangents.capacity(), 3 * kCount);
  AddBoth(inOrder, batched, tris, 10, kCount, all, 2);
  AddBoth(inOrder, batched, tris, 0, kCount, all, 3);
  ExpectSameScene(a, b);
}

TEST(Prefault, KeepsContentsAndReserves) {
  std::vector<uint64_t> v(1000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = i * 2654435761u;
  ReserveOnThreads(v, size_t(3) << 20, 2);  // 24 MiB: paged in on two threads
  ASSERT_GE(v.capacity(), size_t(3) << 20);
  ASSERT_EQ(v.size(), 1000u);
  for (size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], i * 2654435761u);
  v.resize(size_t(3) << 20);  // zeros over the paged-in capacity
  EXPECT_EQ(v.back(), 0u);
  ReserveOnThreads(v, 10);  // never shrinks
  EXPECT_EQ(v.size(), size_t(3) << 20);
  PrefaultOnThreads(nullptr, 0);  // empty spans and spans under a page are left alone
  PrefaultOnThreads(v.data(), 1);
}

}  // namespace
}  // namespace pt
