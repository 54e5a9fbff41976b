// MeshSink::AddBatch (a big primitive's triangles transformed on every core) against Add in
// order: the same triangles, values and skipped ones, bit for bit, over transforms that mirror,
// scale hugely or tinily, and attribute sets that start, stop and backfill the optional arrays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "src/core/prefault.h"
#include "src/io/mesh_common.h"

namespace pt {
namespace {

// Random triangles with attributes; about one in twenty degenerate (a repeated vertex,
// collinear vertices or a non-finite coordinate), and some with zero-length normals.
std::vector<TriangleVertices> RandomTriangles(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto v3 = [&] { return vec3(u(rng), u(rng), u(rng)); };
  std::vector<TriangleVertices> out(count);
  for (size_t t = 0; t < count; ++t) {
    TriangleVertices& v = out[t];
    for (int k = 0; k < 3; ++k) {
      v.p[k] = v3();
      v.normals[k] = v3();
      v.uvs[k] = vec2(u(rng), u(rng));
      v.uvs1[k] = vec2(u(rng), std::nanf(""));
      v.tangents[k] = vec4(v3(), u(rng));
      v.colors[k] = vec4(v3(), 1.0f);
    }
    switch (rng() % 40) {
      case 0: v.p[2] = v.p[0]; break;
      case 1: v.p[2] = 2.0f * v.p[1] - v.p[0]; break;
      case 2: v.p[1].y = std::numeric_limits<float>::infinity(); break;
      case 3: v.normals[1] = vec3(0.0f); break;
      default: break;
    }
  }
  return out;
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

// Adds the triangles [first, last) with attributes `has` one by one into `inOrder` and as one
// batch into `batched`.
void AddBoth(MeshSink& inOrder, MeshSink& batched, const std::vector<TriangleVertices>& tris,
             size_t first, size_t last, const VertexPresence& has, uint32_t material) {
  for (size_t t = first; t < last; ++t) inOrder.Add(tris[t].p, AttributesOf(tris[t], has), material);
  batched.AddBatch(last - first, has, material,
                   [&](size_t t, TriangleVertices& v) { v = tris[first + t]; });
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

TEST(MeshBatch, SameAsAddInOrderOverTransformsAndAttributeSets) {
  // Enough triangles that the batch runs on several threads (2^14 per thread).
  constexpr size_t kCount = 100000;
  std::vector<TriangleVertices> tris = RandomTriangles(kCount, 7);
  for (int which = 0; which < 4; ++which) {
    SCOPED_TRACE("transform " + std::to_string(which));
    SceneDesc a, b;
    MeshSink inOrder(a, Transform(which), -1, "in order"), batched(b, Transform(which), -1, "batch");
    VertexPresence none, all{true, true, true, true, true}, some{true, false, true, false, false};
    // No optional data yet, then data that backfills, then none again (filled), then some.
    AddBoth(inOrder, batched, tris, 0, 1000, none, 3);
    AddBoth(inOrder, batched, tris, 1000, 60000, all, 4);
    AddBoth(inOrder, batched, tris, 60000, 60010, none, 5);
    AddBoth(inOrder, batched, tris, 60010, kCount, some, 6);
    AddBoth(inOrder, batched, tris, 0, 0, all, 7);  // an empty batch adds nothing
    EXPECT_GT(a.skippedDegenerateTriangles, 0);
    EXPECT_EQ(a.triangleColors.size(), a.triangles.size());
    ExpectSameScene(a, b);
  }
}

TEST(MeshBatch, MaterialOverrideAndSingleTriangle) {
  std::vector<TriangleVertices> tris = RandomTriangles(3, 11);
  for (TriangleVertices& v : tris) {
    v.p[0] = vec3(0.0f);
    v.p[1] = vec3(1.0f, 0.0f, 0.0f);
    v.p[2] = vec3(0.0f, 1.0f, 0.0f);
  }
  tris[1].p[2] = tris[1].p[0];  // degenerate: skipped by both
  SceneDesc a, b;
  MeshSink inOrder(a, glm::dmat4(1.0), 2, "in order"), batched(b, glm::dmat4(1.0), 2, "batch");
  AddBoth(inOrder, batched, tris, 0, 1, VertexPresence{}, 9);
  AddBoth(inOrder, batched, tris, 1, 3, VertexPresence{true}, 9);
  EXPECT_EQ(b.triangles.size(), 2u);
  EXPECT_EQ(b.skippedDegenerateTriangles, 1);
  EXPECT_EQ(b.triangleMaterials, (std::vector<uint32_t>{2, 2}));
  ExpectSameScene(a, b);
}

// Room reserved ahead (a scene placing one file again and again) changes no value: the batch
// writes into capacity paged in by ReserveOnThreads.
TEST(MeshBatch, ReservedArraysGiveTheSameScene) {
  constexpr size_t kCount = 70000;
  std::vector<TriangleVertices> tris = RandomTriangles(kCount, 13);
  SceneDesc a, b;
  MeshSink inOrder(a, Transform(2), -1, "in order"), batched(b, Transform(2), -1, "batch");
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
