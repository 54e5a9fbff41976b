// A linear BVH (Karras 2012, "Maximizing parallelism in the construction of BVHs, octrees and
// k-d trees"): the primitives sorted along a Morton curve of their centroids, the hierarchy
// read off the sorted keys (one interior node per pair of neighbouring keys, found
// independently), and the boxes refitted bottom-up. Every stage is a body for one work item,
// run by a GPU kernel (cuda/lbvh_cuda.cu) or by host loops (src/geometry/lbvh_build.cpp) alike.
//
// The tree it emits is BuildBvh's layout (root at 0, children adjacent, leaves of one
// primitive), so the wide layout is collapsed from it as from the SAH tree (bvh_wide.h).
// Its quality is the Morton curve's: the SAH builder's tree is better (docs/bvh.md gives the
// measured costs); it is built in a few passes over the primitives instead of log2(n).
#pragma once

#include <cstdint>
#include <cstring>

#include "src/geometry/aabb.h"
#include "src/scene/scene_types.h"

namespace pt {
namespace lbvh {

// ---- Portable pieces (host and device) ----

PT_HDI int CountLeadingZeros64(uint64_t x) {  // 64 for 0
#if PT_IS_GPU_CODE
  return __clzll(static_cast<long long>(x));
#else
  return x == 0 ? 64 : __builtin_clzll(x);
#endif
}

PT_HDI int CountLeadingZeros32(uint32_t x) {
#if PT_IS_GPU_CODE
  return __clz(static_cast<int>(x));
#else
  return x == 0 ? 32 : __builtin_clz(x);
#endif
}

// Adds v and returns the old value; acquire and release, so that what one thread wrote
// before its add is seen by the thread whose add comes after it.
PT_HDI uint32_t AtomicAdd(uint32_t* p, uint32_t v) {
#if PT_IS_GPU_CODE
  __threadfence();
  const uint32_t old = atomicAdd(p, v);
  __threadfence();
  return old;
#else
  return __atomic_fetch_add(p, v, __ATOMIC_ACQ_REL);
#endif
}

// A box written by another thread of the refit: read past the GPU's L1 (not coherent).
PT_HDI float LoadShared(const float* p) {
#if PT_IS_GPU_CODE
  return __ldcg(p);
#else
  return *p;  // the refit's acquiring add orders it after the other thread's writes
#endif
}

// 21 bits of x spread to every third bit of a 63-bit word.
PT_HDI uint64_t Spread3(uint64_t x) {
  x &= 0x1fffffull;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

// ---- The build's arrays (device or host memory) ----

// Boxes as six float planes: lo.x lo.y lo.z hi.x hi.y hi.z at [k * count + node].
struct Arrays {
  uint32_t n = 0;            // primitives (leaves); interior nodes n - 1
  const Aabb* bounds = nullptr;  // per input primitive
  uint64_t* keys = nullptr;      // Morton codes, sorted with values
  uint32_t* values = nullptr;    // input index of each sorted key
  uint32_t* parent = nullptr;    // [2n - 1]: interior 0..n-2 (root 0), leaf k at n - 1 + k
  uint32_t* left = nullptr;      // [n - 1] per interior node: its children (node numbers)
  uint32_t* right = nullptr;
  uint32_t* rangeLo = nullptr;   // [n - 1] per interior node: its first sorted primitive
  uint32_t* rangeHi = nullptr;   // and its last
  uint32_t* visits = nullptr;    // [n - 1] the refit's arrival counters (zeroed)
  float* box = nullptr;          // [6 (2n - 1)]
  BvhNode* out = nullptr;        // [2n - 1] the tree in BuildBvh's layout
  uint32_t* depth = nullptr;     // [n] each leaf's depth in the tree
};

PT_HDI uint32_t NodeCount(uint32_t n) { return 2 * n - 1; }

// ---- Stage 1: extended Morton codes of the centroids in the centroids' bounds ----
//
// The key interleaves the centroid's cell (18 bits per axis) with a coarse measure of the
// primitive's size (9 bits) in groups of x y z s x y z from the top (Vinkler, Bittner and
// Havran 2017, "Extended Morton codes for high performance BVH construction"): the few
// primitives as big as a room's walls are split off from the small ones near the top of the
// tree instead of widening the boxes of whichever small primitives' subtree they land in. The
// size counts only from 2^16 cells (1/32 of the scene's extent) to 2^22: smaller primitives all
// have size 0 and keep the plain Morton order. On the 3.3M-triangle Breakfast Room with bunnies
// the wide tree's SAH cost went 12.41 -> 11.7, the bunny's Cornell box 4.27 -> 3.5
// (benchmarks/RESULTS.md). Integer arithmetic on the float's bits for the size's logarithm:
// both backends get the same keys, and with them the same tree.

// The size's 9 bits: the box's largest extent in cells, as eighths of an octave (the float's
// exponent and top 3 mantissa bits) from 2^16 to 2^22, scaled to 0..511.
PT_HDI uint64_t SizeBits(const Aabb& b, vec3 cellsPerUnit) {
  const vec3 e = (b.hi - b.lo) * cellsPerUnit;
  const float m = e.x > e.y ? (e.x > e.z ? e.x : e.z) : (e.y > e.z ? e.y : e.z);
  uint32_t bits;
  memcpy(&bits, &m, sizeof bits);
  constexpr int32_t kFirst = (127 + 16) * 8, kSteps = 6 * 8;  // 2^16 .. 2^22 cells
  const int32_t level = int32_t((bits & 0x7fffffffu) >> 20) - kFirst;
  const int32_t u = level < 0 ? 0 : (level > kSteps ? kSteps : level);
  return uint64_t(u) * 511u / uint64_t(kSteps);
}

// sceneLo and invExtent (2^21 / extent per axis, 0 for a flat axis) map centroids to cells.
PT_HDI void MortonCode(const Arrays& a, uint32_t i, vec3 sceneLo, vec3 cellsPerUnit) {
  const Aabb& b = a.bounds[i];
  const vec3 c = 0.5f * b.lo + 0.5f * b.hi;
  auto cell = [](float v) {
    // NaN and negative to 0, large to the last cell.
    return uint64_t(v > 0.0f ? (v < 2097151.0f ? v : 2097151.0f) : 0.0f);
  };
  const uint64_t x = cell((c.x - sceneLo.x) * cellsPerUnit.x) >> 3;
  const uint64_t y = cell((c.y - sceneLo.y) * cellsPerUnit.y) >> 3;
  const uint64_t z = cell((c.z - sceneLo.z) * cellsPerUnit.z) >> 3;
  const uint64_t xyz = Spread3(x) << 2 | Spread3(y) << 1 | Spread3(z);  // 54 bits
  const uint64_t size = SizeBits(b, cellsPerUnit);
  uint64_t key = 0;
  for (int g = 0; g < 9; ++g) {  // x y z s x y z, 7 bits a group
    const uint64_t six = (xyz >> (48 - 6 * g)) & 63u;
    key = key << 7 | (six >> 3) << 4 | ((size >> (8 - g)) & 1u) << 3 | (six & 7u);
  }
  a.keys[i] = key;
  a.values[i] = i;
}

// ---- Stage 2 (the sort) is the backend's ----

// ---- Stage 3: interior node i's key range, split and children (Karras 2012, Fig. 4) ----

// Length of the common prefix of sorted keys i and j (the index breaks ties); -1 outside.
PT_HDI int Delta(const Arrays& a, int i, int j) {
  if (j < 0 || j >= int(a.n)) return -1;
  const uint64_t ki = a.keys[i], kj = a.keys[j];
  if (ki != kj) return CountLeadingZeros64(ki ^ kj);
  return 64 + CountLeadingZeros32(uint32_t(i) ^ uint32_t(j));
}

PT_HDI void EmitInterior(const Arrays& a, uint32_t node) {
  const int i = int(node);
  const int d = Delta(a, i, i + 1) - Delta(a, i, i - 1) >= 0 ? 1 : -1;
  const int deltaMin = Delta(a, i, i - d);
  int lengthMax = 2;
  while (Delta(a, i, i + lengthMax * d) > deltaMin) lengthMax *= 2;
  int length = 0;
  for (int t = lengthMax / 2; t >= 1; t /= 2) {
    if (Delta(a, i, i + (length + t) * d) > deltaMin) length += t;
  }
  const int j = i + length * d;
  const int deltaNode = Delta(a, i, j);
  int split = 0;
  for (int div = 2;; div *= 2) {
    const int t = (length + div - 1) / div;
    if (Delta(a, i, i + (split + t) * d) > deltaNode) split += t;
    if (t <= 1) break;
  }
  const int gamma = i + split * d + (d < 0 ? -1 : 0);
  const int lo = i < j ? i : j, hi = i < j ? j : i;
  const uint32_t leafBase = a.n - 1;
  const uint32_t l = lo == gamma ? leafBase + uint32_t(gamma) : uint32_t(gamma);
  const uint32_t r = hi == gamma + 1 ? leafBase + uint32_t(gamma) + 1 : uint32_t(gamma) + 1;
  a.left[node] = l;
  a.right[node] = r;
  a.rangeLo[node] = uint32_t(lo);
  a.rangeHi[node] = uint32_t(hi);
  a.parent[l] = node;
  a.parent[r] = node;
}

// ---- Stage 4: boxes, from each leaf up while it is the second child to arrive ----

PT_HDI void SetBox(const Arrays& a, uint32_t node, const Aabb& b) {
  const uint32_t count = NodeCount(a.n);
  a.box[0 * count + node] = b.lo.x;
  a.box[1 * count + node] = b.lo.y;
  a.box[2 * count + node] = b.lo.z;
  a.box[3 * count + node] = b.hi.x;
  a.box[4 * count + node] = b.hi.y;
  a.box[5 * count + node] = b.hi.z;
}

PT_HDI Aabb GetBox(const Arrays& a, uint32_t node) {
  const uint32_t count = NodeCount(a.n);
  Aabb b;
  b.lo = vec3(LoadShared(a.box + 0 * count + node), LoadShared(a.box + 1 * count + node),
              LoadShared(a.box + 2 * count + node));
  b.hi = vec3(LoadShared(a.box + 3 * count + node), LoadShared(a.box + 4 * count + node),
              LoadShared(a.box + 5 * count + node));
  return b;
}

PT_HDI void Refit(const Arrays& a, uint32_t leaf) {
  uint32_t node = a.n - 1 + leaf;
  SetBox(a, node, a.bounds[a.values[leaf]]);
  while (node != 0) {
    node = a.parent[node];
    // The first child to arrive leaves; the second has both boxes.
    if (AtomicAdd(&a.visits[node], 1u) == 0) return;
    SetBox(a, node, Union(GetBox(a, a.left[node]), GetBox(a, a.right[node])));
  }
}

// ---- Stage 5: BuildBvh's layout, depth first ----
//
// The collapse to the wide layout (bvh_wide.cpp) needs a node's descendants in one index range
// after it. Depth first with children in pairs: a node of m leaves whose pair of children
// starts at D has its left child's descendants at D + 2 (2 mL - 2 of them) and its right
// child's after them, at D + 2 mL. So D = 2 lo + 1 + 2 t for the first primitive lo of its
// range and the left turns t on its path from the root (the root: D = 1), each found on its
// own by walking up the parents.

PT_HDI uint32_t LeftTurns(const Arrays& a, uint32_t node) {
  uint32_t turns = 0;
  while (node != 0) {
    const uint32_t p = a.parent[node];
    turns += a.left[p] == node ? 1u : 0u;
    node = p;
  }
  return turns;
}

// The node's BvhNode; `pairAt`: where its children's pair goes (interior nodes).
PT_HDI BvhNode OutNode(const Arrays& a, uint32_t node, uint32_t pairAt) {
  const Aabb b = GetBox(a, node);
  const bool leaf = node >= a.n - 1;
  BvhNode out;
  out.boundsMin = b.lo;
  out.boundsMax = b.hi;
  out.leftOrFirst = leaf ? node - (a.n - 1) : pairAt;
  out.count = leaf ? 1u : 0u;
  return out;
}

PT_HDI uint32_t PairAt(const Arrays& a, uint32_t interior, uint32_t turns) {
  return 2 * a.rangeLo[interior] + 1 + 2 * turns;
}

// Work item k < n - 1 writes interior k's children; item n - 1 writes the root.
PT_HDI void EmitLayout(const Arrays& a, uint32_t k) {
  if (k == a.n - 1) {  // interior 0, or the one leaf when n == 1
    a.out[0] = OutNode(a, 0, 1);
    return;
  }
  const uint32_t turns = LeftTurns(a, k), at = PairAt(a, k, turns);
  const uint32_t l = a.left[k], r = a.right[k], leaves = a.n - 1;
  a.out[at] = OutNode(a, l, l < leaves ? PairAt(a, l, turns + 1) : 0);
  a.out[at + 1] = OutNode(a, r, r < leaves ? PairAt(a, r, turns) : 0);
}

// Each leaf's depth (root 0), counted up its parents: the tree must fit the walks' stacks.
PT_HDI void LeafDepth(const Arrays& a, uint32_t leaf) {
  uint32_t node = a.n - 1 + leaf, depth = 0;
  while (node != 0) {
    node = a.parent[node];
    ++depth;
  }
  a.depth[leaf] = depth;
}

}  // namespace lbvh
}  // namespace pt
