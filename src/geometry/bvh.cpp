#include "src/geometry/bvh.h"

#include <algorithm>
#include <cmath>

namespace pt {
namespace {

// SAH costs relative to one primitive test. A GPU pays more for a node (a divergent 64-byte
// fetch of both children) than pbrt-v4's 1/2 assumes: with 1, leaves of a 270k-triangle mesh
// hold ~1.7 primitives instead of ~1, for 17% fewer nodes and the same nodes visited per ray.
constexpr double kTraversalCost = 1.0;
constexpr double kIntersectCost = 1.0;
constexpr int kMaxBins = 256;

// Areas in double: scenes up to 1e19 units across would overflow a float area.
double Area(const Aabb& b) {
  if (b.IsEmpty()) return 0.0;
  double dx = double(b.hi.x) - b.lo.x, dy = double(b.hi.y) - b.lo.y, dz = double(b.hi.z) - b.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

// One primitive as the builder moves it around: bounds and input index in 32 bytes, permuted
// in place so every pass reads memory in order (indexing a bounds array through a shuffled
// permutation made the build cache-miss bound, ~10x slower at 270k primitives).
struct BuildPrim {
  vec3 lo;
  uint32_t index;
  vec3 hi;
  uint32_t pad;

  float Centroid(int axis) const { return 0.5f * lo[axis] + 0.5f * hi[axis]; }  // as Aabb
  vec3 Centroid() const { return 0.5f * lo + 0.5f * hi; }
  Aabb Bounds() const { return Aabb{lo, hi}; }
};

struct Bin {
  Aabb bounds;
  uint32_t count = 0;
};

struct Split {
  int axis = -1;      // -1: no usable plane (all centroids equal, or non-finite extents)
  int bin = 0;        // bins [0, bin] go left
  double cost = 0.0;  // sum over sides of count * area (not yet divided by the node area)
};

// Maps a centroid coordinate to its bin the same way for binning and for partitioning; a NaN
// or out-of-range value is clamped instead of converting an invalid float to int.
struct BinMapper {
  float lo = 0.0f;
  float scale = 0.0f;
  int count = 1;
  int operator()(float c) const {
    float f = (c - lo) * scale;
    if (!(f > 0.0f)) return 0;
    return f < float(count) ? std::min(int(f), count - 1) : count - 1;
  }
};

class Builder {
 public:
  Builder(const std::vector<Aabb>& bounds, const BvhBuildOptions& options, int maxDepth,
          BvhBuildResult* out)
      : out_(out) {
    maxLeafSize_ = std::max(1, options.maxLeafSize);
    maxDepth_ = std::clamp(maxDepth, 0, kBvhMaxDepth);
    binCount_ = std::clamp(options.binCount, 2, kMaxBins);
    bins_.resize(3 * size_t(binCount_));
    rightCost_.resize(binCount_);
    prims_.resize(bounds.size());
    for (size_t i = 0; i < bounds.size(); ++i) {
      prims_[i] = BuildPrim{bounds[i].lo, uint32_t(i), bounds[i].hi, 0};
    }
  }

  void Build(uint32_t nodeIndex, uint32_t begin, uint32_t end, int depth);
  void WriteOrder() {
    for (size_t i = 0; i < prims_.size(); ++i) out_->primOrder[i] = prims_[i].index;
  }

 private:
  Split FindSplit(uint32_t begin, uint32_t end, const Aabb& centroidBounds, BinMapper mappers[3]);
  void MakeLeaf(uint32_t nodeIndex, uint32_t begin, uint32_t end, int depth) {
    out_->nodes[nodeIndex].leftOrFirst = begin;
    out_->nodes[nodeIndex].count = end - begin;
    out_->maxDepth = std::max(out_->maxDepth, depth);
  }

  std::vector<BuildPrim> prims_;
  std::vector<Bin> bins_;          // scratch: binCount_ bins per axis
  std::vector<double> rightCost_;  // scratch: cost of the right side of each plane
  BvhBuildResult* out_;
  int maxLeafSize_ = 4;
  int binCount_ = 16;
  int maxDepth_ = kBvhMaxDepth;
};

Split Builder::FindSplit(uint32_t begin, uint32_t end, const Aabb& centroidBounds,
                         BinMapper mappers[3]) {
  std::fill(bins_.begin(), bins_.end(), Bin{});
  Bin* bins[3] = {&bins_[0], &bins_[binCount_], &bins_[2 * size_t(binCount_)]};
  bool usable[3];
  for (int axis = 0; axis < 3; ++axis) {
    float extent = centroidBounds.hi[axis] - centroidBounds.lo[axis];
    usable[axis] = extent > 0.0f && std::isfinite(extent);
    mappers[axis] = {centroidBounds.lo[axis], usable[axis] ? binCount_ / extent : 0.0f, binCount_};
  }
  for (uint32_t i = begin; i < end; ++i) {
    const BuildPrim& prim = prims_[i];
    vec3 c = prim.Centroid();
    for (int axis = 0; axis < 3; ++axis) {
      Bin& bin = bins[axis][mappers[axis](c[axis])];
      bin.bounds.Extend(prim.Bounds());
      ++bin.count;
    }
  }
  // Sweep from the right, then from the left, scoring the plane after each bin. A plane after
  // an empty bin scores the same as the one before it, so areas are computed only where a bin
  // adds something (most bins of a small node are empty).
  Split best;
  std::vector<double>& rightCost = rightCost_;
  for (int axis = 0; axis < 3; ++axis) {
    if (!usable[axis]) continue;
    const Bin* b = bins[axis];
    Aabb acc;
    uint32_t count = 0;
    double cost = -1.0;
    for (int i = binCount_ - 1; i > 0; --i) {
      if (b[i].count > 0) {
        acc.Extend(b[i].bounds);
        count += b[i].count;
        cost = count * Area(acc);
      }
      rightCost[i] = cost;
    }
    acc = Aabb();
    count = 0;
    for (int i = 0; i < binCount_ - 1; ++i) {
      if (b[i].count == 0) continue;
      acc.Extend(b[i].bounds);
      count += b[i].count;
      if (rightCost[i + 1] < 0.0) break;  // nothing right of here
      double total = count * Area(acc) + rightCost[i + 1];
      if (best.axis < 0 || total < best.cost) best = {axis, i, total};
    }
  }
  return best;
}

void Builder::Build(uint32_t nodeIndex, uint32_t begin, uint32_t end, int depth) {
  Aabb nodeBounds, centroidBounds;
  for (uint32_t i = begin; i < end; ++i) {
    nodeBounds.Extend(prims_[i].Bounds());
    centroidBounds.Extend(prims_[i].Centroid());
  }
  out_->nodes[nodeIndex].boundsMin = nodeBounds.lo;
  out_->nodes[nodeIndex].boundsMax = nodeBounds.hi;
  uint32_t n = end - begin;
  if (n <= 1 || depth >= maxDepth_) return MakeLeaf(nodeIndex, begin, end, depth);

  BinMapper mappers[3];
  Split split = FindSplit(begin, end, centroidBounds, mappers);
  bool fits = n <= uint32_t(maxLeafSize_);
  uint32_t mid;
  if (split.axis < 0) {
    if (fits) return MakeLeaf(nodeIndex, begin, end, depth);
    mid = begin + n / 2;  // identical centroids: the index order is as good as any
  } else {
    double area = Area(nodeBounds);
    double splitCost = kTraversalCost + kIntersectCost * split.cost / area;
    if (fits && (!(area > 0.0) || !(splitCost < kIntersectCost * n))) {
      return MakeLeaf(nodeIndex, begin, end, depth);
    }
    const BinMapper& mapper = mappers[split.axis];
    int axis = split.axis, bin = split.bin;
    auto first = prims_.begin();
    mid = uint32_t(
        std::partition(first + begin, first + end,
                       [&](const BuildPrim& p) { return mapper(p.Centroid(axis)) <= bin; }) -
        first);
    if (mid == begin || mid == end) mid = begin + n / 2;  // unreachable: both sides counted
  }

  uint32_t left = uint32_t(out_->nodes.size());
  out_->nodes.resize(out_->nodes.size() + 2);
  out_->nodes[nodeIndex].leftOrFirst = left;
  out_->nodes[nodeIndex].count = 0;
  Build(left, begin, mid, depth + 1);  // recursion depth <= kBvhMaxDepth
  Build(left + 1, mid, end, depth + 1);
}

}  // namespace

BvhBuildResult BuildBvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                        int maxDepth) {
  BvhBuildResult result;
  uint32_t n = uint32_t(primBounds.size());
  result.primOrder.resize(n);
  result.nodes.reserve(n > 0 ? 2 * size_t(n) - 1 : 1);
  result.nodes.push_back(BvhNode{});
  if (n == 0) {  // an empty root: count 0 and empty bounds, which every ray misses
    result.nodes[0].boundsMin = Aabb().lo;
    result.nodes[0].boundsMax = Aabb().hi;
    result.nodes[0].leftOrFirst = 0;
    result.nodes[0].count = 0;
    return result;
  }
  Builder builder(primBounds, options, maxDepth, &result);
  builder.Build(0, 0, n, 0);
  builder.WriteOrder();
  return result;
}

}  // namespace pt
