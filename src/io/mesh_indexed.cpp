// MeshSink::AddIndexed: an indexed primitive's vertices transformed once each, then its
// triangles gathered, tested and stored in the scene's arrays in place, a big primitive on
// every core. The values are Add's (the same per-vertex functions), in Add's order.
#include <algorithm>
#include <thread>
#include <utility>

#include "src/core/parallel_ranges.h"
#include "src/io/mesh_common.h"

namespace pt {
namespace {

// Triangles (or vertices) per thread below which a primitive stays on one thread.
constexpr size_t kMinPerThread = 1 << 12;

// Makes room for `count` more triangles in an optional per-triangle array: backfilled with
// `fill` when the primitive brings the data (Add's rule: the array exists from the first
// triangle with data), else grown with `fill` once the array exists.
template <typename T>
void GrowOptional(std::vector<T>& all, size_t base, size_t count, bool has, T fill = T{}) {
  if (!has && all.empty()) return;
  all.resize(base, fill);
  all.resize(base + count, fill);
}

// Moves `count` elements of a per-triangle array from `from` down to `to` (to <= from).
template <typename T>
void MoveDown(std::vector<T>& all, size_t from, size_t to, size_t count) {
  if (all.size() < from + count || from == to) return;
  std::copy(all.begin() + ptrdiff_t(from), all.begin() + ptrdiff_t(from + count),
            all.begin() + ptrdiff_t(to));
}

// The primitive's vertices in world space, each once.
struct WorldVertices {
  std::vector<vec3> positions, normals;
  std::vector<unsigned char> normalValid;
  std::vector<vec4> tangents;
};

}  // namespace

void MeshSink::GrowTriangles(size_t base, size_t count, const VertexPresence& has,
                             uint32_t material) {
  scene_.triangles.resize(base + count);
  scene_.triangleNormals.resize(base + count);
  scene_.triangleMaterials.resize(base + count, HasOverride() ? Override() : material);
  GrowOptional(scene_.triangleUvs, base, count, has.uvs);
  GrowOptional(scene_.triangleUvs1, base, count, has.uvs1);
  GrowOptional(scene_.triangleTangents, base, count, has.tangents);
  GrowOptional(scene_.triangleColors, base, count, has.colors, kWhiteColors);
}

MeshSink::OptionalArrays MeshSink::Optionals() const {
  return {!scene_.triangleUvs.empty(), !scene_.triangleUvs1.empty(),
          !scene_.triangleTangents.empty(), !scene_.triangleColors.empty()};
}

// Optional arrays that did not exist before a primitive whose every triangle was skipped do
// not exist after it either (as with Add: an array starts at the first triangle with data).
void MeshSink::KeepAbsent(const OptionalArrays& before) {
  if (!before.uvs) scene_.triangleUvs.clear();
  if (!before.uvs1) scene_.triangleUvs1.clear();
  if (!before.tangents) scene_.triangleTangents.clear();
  if (!before.colors) scene_.triangleColors.clear();
}

// Every per-triangle array cut to `size` triangles (the optional ones only where they exist).
void MeshSink::ShrinkTriangles(size_t size) {
  scene_.triangles.resize(size);
  scene_.triangleNormals.resize(size);
  scene_.triangleMaterials.resize(size);
  if (!scene_.triangleUvs.empty()) scene_.triangleUvs.resize(size);
  if (!scene_.triangleUvs1.empty()) scene_.triangleUvs1.resize(size);
  if (!scene_.triangleTangents.empty()) scene_.triangleTangents.resize(size);
  if (!scene_.triangleColors.empty()) scene_.triangleColors.resize(size);
}

void MeshSink::AddIndexed(const IndexedVertices& v, const std::vector<uint32_t>& indices,
                          uint32_t material) {
  const VertexPresence has = v.Presence();
  const size_t vertices = v.positions.size(), count = indices.size() / 3;
  if (count == 0) return;
  WorldVertices w;
  w.positions.resize(vertices);
  if (has.normals) w.normals.resize(vertices), w.normalValid.resize(vertices);
  if (has.tangents) w.tangents.resize(vertices);
  ForRangesOnThreads(vertices, 0, kMinPerThread, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) {
      w.positions[i] = WorldPosition(v.positions[i]);
      if (has.normals) {
        bool valid = false;
        w.normals[i] = WorldNormal(v.normals[i], valid);
        w.normalValid[i] = valid;
      }
      if (has.tangents) w.tangents[i] = WorldTangent(v.tangents[i]);
    }
  });
  const size_t base = scene_.triangles.size();
  const OptionalArrays before = Optionals();
  GrowTriangles(base, count, has, material);
  const size_t cores = std::max(1u, std::thread::hardware_concurrency());
  const size_t ranges = std::clamp<size_t>(count / kMinPerThread, 1, cores);
  auto first = [&](size_t r) { return count * r / ranges; };
  std::vector<size_t> kept(ranges);
  ForRangesOnThreads(ranges, int(ranges), 1, [&](size_t lo, size_t hi) {
    for (size_t r = lo; r < hi; ++r) {
      size_t out = base + first(r);
      for (size_t t = first(r); t < first(r + 1); ++t) {
        // Under a mirroring transform vertices 1 and 2 trade places (Add's rule).
        uint32_t i[3] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
        if (mirrored_) std::swap(i[1], i[2]);
        const vec3 &p0 = w.positions[i[0]], &p1 = w.positions[i[1]], &p2 = w.positions[i[2]];
        if (IsDegenerateTriangle(p0, p1, p2)) continue;
        scene_.triangles[out] = Triangle{p0, p1, p2};
        bool normals = has.normals && w.normalValid[i[0]] && w.normalValid[i[1]] &&
                       w.normalValid[i[2]];
        scene_.triangleNormals[out] =
            normals ? TriangleNormals{w.normals[i[0]], w.normals[i[1]], w.normals[i[2]]}
                    : TriangleNormals{};
        if (has.uvs) {
          vec2 uv[3] = {v.uvs[i[0]], v.uvs[i[1]], v.uvs[i[2]]};
          scene_.triangleUvs[out] = FiniteUvs(uv);
        }
        if (has.uvs1) {
          vec2 uv[3] = {v.uvs1[i[0]], v.uvs1[i[1]], v.uvs1[i[2]]};
          scene_.triangleUvs1[out] = FiniteUvs(uv);
        }
        if (has.tangents)
          scene_.triangleTangents[out] = {w.tangents[i[0]], w.tangents[i[1]], w.tangents[i[2]]};
        if (has.colors)
          scene_.triangleColors[out] = {v.colors[i[0]], v.colors[i[1]], v.colors[i[2]]};
        ++out;
      }
      kept[r] = out - (base + first(r));
    }
  });
  // Close the gaps skipped (degenerate) triangles left, in range order.
  size_t at = base + kept[0];
  for (size_t r = 1; r < ranges; ++r) {
    size_t from = base + first(r);
    if (from != at) {
      MoveDown(scene_.triangles, from, at, kept[r]);
      MoveDown(scene_.triangleNormals, from, at, kept[r]);
      if (has.uvs) MoveDown(scene_.triangleUvs, from, at, kept[r]);
      if (has.uvs1) MoveDown(scene_.triangleUvs1, from, at, kept[r]);
      if (has.tangents) MoveDown(scene_.triangleTangents, from, at, kept[r]);
      if (has.colors) MoveDown(scene_.triangleColors, from, at, kept[r]);
    }
    at += kept[r];
  }
  scene_.skippedDegenerateTriangles += int(base + count - at);
  ShrinkTriangles(at);
  if (at == base) KeepAbsent(before);
}

}  // namespace pt
