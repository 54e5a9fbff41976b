#include "src/geometry/lbvh_build.h"

#include <algorithm>
#include <cstring>
#include <thread>

#include "src/geometry/lbvh_collapse.h"

namespace pt {
namespace {

// body(i) for i in [0, n), in contiguous chunks on `threads` threads.
template <typename F>
void HostFor(uint32_t n, int threads, const F& body) {
  const uint32_t chunks = uint32_t(std::max(1, std::min<int>(threads, int(n / 4096) + 1)));
  auto run = [&](uint32_t c) {
    const uint32_t begin = uint32_t(uint64_t(n) * c / chunks);
    const uint32_t end = uint32_t(uint64_t(n) * (c + 1) / chunks);
    for (uint32_t i = begin; i < end; ++i) body(i);
  };
  std::vector<std::thread> pool;
  for (uint32_t c = 1; c < chunks; ++c) pool.emplace_back(run, c);
  run(0);
  for (std::thread& t : pool) t.join();
}

// Stable LSD radix sort of (key, value) pairs by key, 8 bits a pass; passes whose digit is the
// same for every key are skipped (a Morton code of 63 bits over a small grid has several).
void RadixSortPairs(std::vector<uint64_t>& keys, std::vector<uint32_t>& values) {
  const size_t n = keys.size();
  std::vector<uint64_t> keys2(n);
  std::vector<uint32_t> values2(n);
  for (int shift = 0; shift < 64; shift += 8) {
    size_t count[256] = {};
    for (uint64_t k : keys) ++count[(k >> shift) & 0xff];
    if (std::count(count, count + 256, n) == 1) continue;  // one digit for all
    size_t offset = 0;
    for (size_t& c : count) {
      const size_t here = c;
      c = offset;
      offset += here;
    }
    for (size_t i = 0; i < n; ++i) {
      const size_t to = count[(keys[i] >> shift) & 0xff]++;
      keys2[to] = keys[i];
      values2[to] = values[i];
    }
    keys.swap(keys2);
    values.swap(values2);
  }
}

// The linear BVH's arrays on the host, through the refit (lbvh.h's stages 1-4).
struct HostLbvh {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> values, parent, left, right, rangeLo, rangeHi, visits;
  std::vector<float> box;
  lbvh::Arrays a;

  HostLbvh(const std::vector<Aabb>& bounds, int threads) {
    const uint32_t n = uint32_t(bounds.size());
    keys.resize(n), values.resize(n), parent.resize(lbvh::NodeCount(n));
    left.resize(n - 1), right.resize(n - 1), rangeLo.resize(n - 1), rangeHi.resize(n - 1);
    visits.assign(n - 1, 0u);
    box.resize(6 * size_t(lbvh::NodeCount(n)));
    a.n = n;
    a.bounds = bounds.data();
    a.keys = keys.data();
    a.values = values.data();
    Point();
    vec3 lo, cells;
    LbvhGrid(bounds, &lo, &cells);
    HostFor(n, threads, [&](uint32_t i) { lbvh::MortonCode(a, i, lo, cells); });
    RadixSortPairs(keys, values);
    Point();  // the sort swapped buffers
    HostFor(n - 1, threads, [&](uint32_t i) { lbvh::EmitInterior(a, i); });
    HostFor(n, threads, [&](uint32_t i) { lbvh::Refit(a, i); });
  }
  void Point() {
    a.keys = keys.data();
    a.values = values.data();
    a.parent = parent.data();
    a.left = left.data();
    a.right = right.data();
    a.rangeLo = rangeLo.data();
    a.rangeHi = rangeHi.data();
    a.visits = visits.data();
    a.box = box.data();
  }
};

// The wide nodes a level at a time from the root (lbvh_collapse.h's CountLevel and EmitNode,
// with the scans between them); false when deeper than the walks' stack.
bool EmitWideLevels(const lbvh::Arrays& a, lbvh::CollapseArrays c, int threads,
                    WideBvhResult* out) {
  const uint32_t n = a.n;
  out->nodes.assign(n, WideBvhNode{});
  out->primOrder.assign(n, 0u);
  std::vector<float> sah(n, 0.0f);
  c.wide = out->nodes.data();
  c.primOrder = out->primOrder.data();
  c.sah = sah.data();
  std::vector<uint32_t> taskNode{0u}, taskWide{0u}, nextNode, nextWide;
  std::vector<uint32_t> children, count, interior, prims, interiorOffset, primOffset;
  uint32_t nodeCount = 1, primCount = 0;
  int depth = 0;
  for (; !taskNode.empty(); ++depth) {
    if (depth >= kWideStackSize) return false;
    const uint32_t f = uint32_t(taskNode.size());
    children.resize(size_t(f) * lbvh::kCollapseWidth);
    count.resize(f), interior.resize(f), prims.resize(f);
    interiorOffset.resize(f), primOffset.resize(f);
    c.taskNode = taskNode.data();
    c.taskWide = taskWide.data();
    c.taskChildren = children.data();
    c.taskCount = count.data();
    c.taskInterior = interior.data();
    c.taskPrims = prims.data();
    HostFor(f, threads, [&](uint32_t t) { lbvh::CountLevel(a, c, t); });
    uint32_t interiorTotal = 0, primTotal = 0;
    for (uint32_t t = 0; t < f; ++t) {
      interiorOffset[t] = interiorTotal;
      primOffset[t] = primTotal;
      interiorTotal += interior[t];
      primTotal += prims[t];
    }
    nextNode.resize(interiorTotal);
    nextWide.resize(interiorTotal);
    c.interiorOffset = interiorOffset.data();
    c.primOffset = primOffset.data();
    c.nodeBase = nodeCount;
    c.primBase = primCount;
    c.nextNode = nextNode.data();
    c.nextWide = nextWide.data();
    HostFor(f, threads, [&](uint32_t t) { lbvh::EmitNode(a, c, t); });
    nodeCount += interiorTotal;
    primCount += primTotal;
    taskNode.swap(nextNode);
    taskWide.swap(nextWide);
  }
  out->nodes.resize(nodeCount);
  out->maxDepth = depth - 1;
  double total = 0.0;
  for (uint32_t i = 0; i < nodeCount; ++i) total += double(sah[i]);
  const float rootArea = lbvh::BoxArea(lbvh::GetBox(a, 0));
  out->sahCost = rootArea > 0.0f ? total / rootArea : 0.0;
  return primCount == n;
}

}  // namespace

void LbvhGrid(const std::vector<Aabb>& bounds, vec3* sceneLo, vec3* cellsPerUnit) {
  Aabb centroids;
  for (const Aabb& b : bounds) centroids.Extend(0.5f * b.lo + 0.5f * b.hi);
  *sceneLo = centroids.IsEmpty() ? vec3(0.0f) : centroids.lo;
  const vec3 extent = centroids.IsEmpty() ? vec3(0.0f) : centroids.hi - centroids.lo;
  for (int a = 0; a < 3; ++a) {
    // A flat (or non-finite) axis maps every centroid to cell 0.
    const float e = extent[a];
    (*cellsPerUnit)[a] = e > 0.0f && e < kInfinity ? float(2097152.0 / double(e)) : 0.0f;
  }
}

bool FinishLbvh(const std::vector<uint32_t>& depths, BvhBuildResult* out) {
  uint32_t deepest = 0;
  for (uint32_t d : depths) deepest = std::max(deepest, d);
  out->maxDepth = int(deepest);
  return deepest <= uint32_t(kBvhMaxDepth);
}

BvhBuildResult BuildLbvhHost(const std::vector<Aabb>& bounds, int threads) {
  if (threads <= 0) threads = std::max(1, int(std::thread::hardware_concurrency()));
  BvhBuildResult out;
  const uint32_t n = uint32_t(bounds.size());
  if (n == 0) {  // BuildBvh's empty tree: one root of no primitives
    BvhNode root{};
    root.boundsMin = Aabb().lo;
    root.boundsMax = Aabb().hi;
    out.nodes.push_back(root);
    return out;
  }
  HostLbvh h(bounds, threads);
  std::vector<uint32_t> depth(n);
  out.nodes.resize(lbvh::NodeCount(n));
  h.a.out = out.nodes.data();
  h.a.depth = depth.data();
  HostFor(n, threads, [&](uint32_t i) { lbvh::EmitLayout(h.a, i); });
  HostFor(n, threads, [&](uint32_t i) { lbvh::LeafDepth(h.a, i); });
  out.primOrder = h.values;
  if (!FinishLbvh(depth, &out)) {
    // Deeper than the walks' stacks: the SAH builder's tree (depth-capped) instead.
    BvhBuildOptions options;
    options.maxLeafSize = 1;
    options.threads = threads;
    return BuildBvh(bounds, options);
  }
  return out;
}

bool CollapseLbvhHost(const std::vector<Aabb>& bounds, int threads, WideBvhResult* out) {
  if (threads <= 0) threads = std::max(1, int(std::thread::hardware_concurrency()));
  const uint32_t n = uint32_t(bounds.size());
  if (n < 2) return false;
  HostLbvh h(bounds, threads);
  const uint32_t nodes = lbvh::NodeCount(n);
  std::vector<float> cost(size_t(nodes) * lbvh::kCollapseWidth);
  std::vector<int8_t> choice(cost.size()), split8(nodes);
  std::vector<uint8_t> asLeaf(nodes);
  std::vector<uint32_t> visits(n - 1, 0u);
  lbvh::CollapseArrays c;
  c.cost = cost.data();
  c.choice = choice.data();
  c.split8 = split8.data();
  c.asLeaf = asLeaf.data();
  c.visits = visits.data();
  HostFor(n, threads, [&](uint32_t i) { lbvh::CollapseCosts(h.a, c, i); });
  return EmitWideLevels(h.a, c, threads, out);
}

}  // namespace pt
