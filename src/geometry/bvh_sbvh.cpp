// Spatial-split BVH (Stich, Friedrich, Dietrich 2009, "Spatial Splits in Bounding Volume
// Hierarchies"): at each node the best binned object split competes with the best binned
// spatial split, which cuts space rather than the primitive list, so a primitive that
// straddles the plane goes to both sides with its bounds clipped to each. Reference
// unsplitting keeps a straddler on one side when that is cheaper. Duplicates are limited by a
// budget (30% of the primitives) shared down the tree in proportion to subtree size, so the
// tree does not depend on the thread count.
#include <cmath>

#include "src/geometry/bvh_build_internal.h"

namespace pt {
namespace bvh_internal {
namespace {

constexpr int kSpatialBins = 32;
constexpr double kDuplicateBudget = 0.3;  // at most this many extra references per primitive
// Spatial splits are tried only where the object split's children overlap by more than this
// fraction of the root's area (the paper's alpha): elsewhere they cannot win by much.
constexpr double kOverlapAlpha = 1e-5;

struct SpatialBin {
  Aabb bounds;
  uint32_t enter = 0, exit = 0;
};

struct SpatialSplit {
  int axis = -1;
  float plane = 0.0f;
  double cost = 0.0;  // count * area summed over sides
  Aabb left, right;
  uint32_t leftCount = 0, rightCount = 0;
};

Aabb Clip(const Aabb& a, const Aabb& b) {
  Aabb r{glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
  return r.IsEmpty() ? Aabb() : r;
}

class SbvhBuilder {
 public:
  SbvhBuilder(const std::vector<Aabb>& bounds, const BvhBuildOptions& options, int maxDepth,
              const PrimClipper& clip)
      : bounds_(bounds), clip_(clip), runner_(BuildThreads(options.threads)) {
    maxLeafSize_ = std::max(1, options.maxLeafSize);
    maxDepth_ = std::clamp(maxDepth, 0, kBvhMaxDepth);
    binCount_ = std::clamp(options.binCount, 2, kMaxBins);
  }

  void Build(BvhBuildResult* out) {
    Task root;
    root.refs.resize(bounds_.size());
    for (size_t i = 0; i < bounds_.size(); ++i) {
      root.refs[i] = BuildPrim{bounds_[i].lo, uint32_t(i), bounds_[i].hi, 0};
      root.bounds.Extend(bounds_[i]);
    }
    rootArea_ = Area(root.bounds);
    root.budget = kDuplicateBudget * double(bounds_.size());
    runner_.Spawn(std::move(root));
    runner_.Run([&](Task& task) {
      BinScratch scratch(binCount_);
      std::vector<BuildPrim> refs = std::move(task.refs);
      Node(task, scratch, std::move(refs), task.bounds, task.depth, task.budget);
    });
    FlattenTasks(runner_, out);
  }

 private:
  uint32_t Node(Task& task, BinScratch& scratch, std::vector<BuildPrim> refs, const Aabb& bounds,
                int depth, double budget);
  SpatialSplit FindSpatialSplit(const std::vector<BuildPrim>& refs, const Aabb& bounds);
  void SplitSpatially(std::vector<BuildPrim>& refs, const SpatialSplit& split,
                      std::vector<BuildPrim>* left, std::vector<BuildPrim>* right);
  uint32_t Leaf(Task& task, uint32_t index, const std::vector<BuildPrim>& refs) {
    TaskNode& node = task.nodes[index];
    node.leaf = true;
    node.first = uint32_t(task.leafPrims.size());
    node.count = uint32_t(refs.size());
    for (const BuildPrim& r : refs) task.leafPrims.push_back(r.index);
    return index;
  }
  uint32_t Child(Task& task, BinScratch& scratch, std::vector<BuildPrim> refs, const Aabb& bounds,
                 int depth, double budget) {
    if (refs.size() < kMinTaskPrims || runner_.Threads() == 1)
      return Node(task, scratch, std::move(refs), bounds, depth, budget);
    Task sub;
    sub.refs = std::move(refs);
    sub.bounds = bounds;
    sub.depth = depth;
    sub.budget = budget;
    return kTaskRef | runner_.Spawn(std::move(sub));
  }

  const std::vector<Aabb>& bounds_;
  const PrimClipper& clip_;
  TaskRunner runner_;
  double rootArea_ = 0.0;
  int maxLeafSize_ = 4;
  int binCount_ = 16;
  int maxDepth_ = kBvhMaxDepth;
};

SpatialSplit SbvhBuilder::FindSpatialSplit(const std::vector<BuildPrim>& refs, const Aabb& bounds) {
  SpatialSplit best;
  SpatialBin bins[kSpatialBins];
  for (int axis = 0; axis < 3; ++axis) {
    double lo = bounds.lo[axis], extent = double(bounds.hi[axis]) - lo;
    if (!(extent > 0.0) || !std::isfinite(extent)) continue;
    double binSize = extent / kSpatialBins;
    auto binOf = [&](float x) {
      int b = int((double(x) - lo) / binSize);
      return std::clamp(b, 0, kSpatialBins - 1);
    };
    auto planeAt = [&](int b) { return float(lo + binSize * b); };  // left plane of bin b
    for (SpatialBin& b : bins) b = SpatialBin{};
    for (const BuildPrim& r : refs) {
      int first = binOf(r.lo[axis]), last = binOf(r.hi[axis]);
      ++bins[first].enter;
      ++bins[last].exit;
      Aabb rest = r.Bounds();
      for (int b = first; b < last; ++b) {  // clip the part in bin b off the reference
        Aabb slab = bounds;
        slab.lo[axis] = b == first ? rest.lo[axis] : planeAt(b);
        slab.hi[axis] = planeAt(b + 1);
        bins[b].bounds.Extend(Clip(clip_(r.index, slab), rest));
        rest.lo[axis] = planeAt(b + 1);
      }
      bins[last].bounds.Extend(Clip(clip_(r.index, rest), r.Bounds()));
    }
    // Sweep: planes between bins; left holds references entering at or before the plane.
    Aabb rightBounds[kSpatialBins];
    uint32_t rightCount[kSpatialBins];
    Aabb acc;
    uint32_t count = 0;
    for (int b = kSpatialBins - 1; b > 0; --b) {
      acc.Extend(bins[b].bounds);
      count += bins[b].exit;
      rightBounds[b] = acc;
      rightCount[b] = count;
    }
    acc = Aabb();
    count = 0;
    for (int b = 0; b < kSpatialBins - 1; ++b) {
      acc.Extend(bins[b].bounds);
      count += bins[b].enter;
      uint32_t rc = rightCount[b + 1];
      if (count == 0 || rc == 0) continue;
      double cost = count * Area(acc) + rc * Area(rightBounds[b + 1]);
      if (best.axis < 0 || cost < best.cost) {
        best = {axis, planeAt(b + 1), cost, acc, rightBounds[b + 1], count, rc};
      }
    }
  }
  return best;
}

// Sends each reference left, right, or (clipped) to both; a straddler stays on one side when
// that costs less than splitting it (unsplitting, the paper's section 4.4).
void SbvhBuilder::SplitSpatially(std::vector<BuildPrim>& refs, const SpatialSplit& split,
                                 std::vector<BuildPrim>* left, std::vector<BuildPrim>* right) {
  int axis = split.axis;
  float plane = split.plane;
  Aabb lb = split.left, rb = split.right;
  double nl = split.leftCount, nr = split.rightCount;
  for (const BuildPrim& r : refs) {
    if (r.hi[axis] <= plane) {
      left->push_back(r);
    } else if (r.lo[axis] >= plane) {
      right->push_back(r);
    } else {
      Aabb box = r.Bounds();
      double costSplit = Area(lb) * nl + Area(rb) * nr;
      double costLeft = Area(Union(lb, box)) * nl + Area(rb) * (nr - 1);
      double costRight = Area(lb) * (nl - 1) + Area(Union(rb, box)) * nr;
      if (costLeft < costSplit && costLeft <= costRight) {
        left->push_back(r);
        lb.Extend(box);
        nr -= 1;
      } else if (costRight < costSplit) {
        right->push_back(r);
        rb.Extend(box);
        nl -= 1;
      } else {
        Aabb lpart = box, rpart = box;
        lpart.hi[axis] = plane;
        rpart.lo[axis] = plane;
        lpart = Clip(clip_(r.index, lpart), box);
        rpart = Clip(clip_(r.index, rpart), box);
        if (!lpart.IsEmpty()) left->push_back(BuildPrim{lpart.lo, r.index, lpart.hi, 0});
        if (!rpart.IsEmpty()) right->push_back(BuildPrim{rpart.lo, r.index, rpart.hi, 0});
        if (lpart.IsEmpty() && rpart.IsEmpty()) left->push_back(r);  // clipping lost it: keep
      }
    }
  }
}

uint32_t SbvhBuilder::Node(Task& task, BinScratch& scratch, std::vector<BuildPrim> refs,
                           const Aabb& bounds, int depth, double budget) {
  uint32_t index = uint32_t(task.nodes.size());
  task.nodes.emplace_back();
  task.nodes[index].bounds = bounds;
  uint32_t n = uint32_t(refs.size());
  if (n <= 1 || depth >= maxDepth_) return Leaf(task, index, refs);

  Aabb centroids;
  for (const BuildPrim& r : refs) centroids.Extend(r.Centroid());
  BinMapper mappers[3];
  Split object = FindObjectSplit(refs.data(), n, centroids, binCount_, scratch, mappers);
  SpatialSplit spatial;
  double area = Area(bounds);
  bool overlapping = object.axis >= 0 &&
                     Area(Clip(object.left, object.right)) > kOverlapAlpha * rootArea_;
  if ((object.axis < 0 || overlapping) && budget >= 1.0) spatial = FindSpatialSplit(refs, bounds);
  bool useSpatial = spatial.axis >= 0 && (object.axis < 0 || spatial.cost < object.cost);
  double bestCost = useSpatial ? spatial.cost : object.cost;
  bool fits = n <= uint32_t(maxLeafSize_);
  if (object.axis < 0 && !useSpatial && fits) return Leaf(task, index, refs);
  if (fits && (object.axis >= 0 || useSpatial) &&
      (!(area > 0.0) || !(kTraversalCost + kIntersectCost * bestCost / area < kIntersectCost * n))) {
    return Leaf(task, index, refs);
  }

  std::vector<BuildPrim> left, right;
  Aabb lb, rb;
  if (useSpatial) {
    SplitSpatially(refs, spatial, &left, &right);
  } else if (object.axis >= 0) {
    Aabb lc, rc;
    uint32_t mid = PartitionObjects(refs.data(), n, object, mappers[object.axis], &lc, &rc);
    if (mid == 0 || mid == n) mid = n / 2;  // unreachable: both sides counted
    left.assign(refs.begin(), refs.begin() + mid);
    right.assign(refs.begin() + mid, refs.end());
  } else {  // identical centroids and too many to fit a leaf: split the list in half
    left.assign(refs.begin(), refs.begin() + n / 2);
    right.assign(refs.begin() + n / 2, refs.end());
  }
  if (left.empty() || right.empty()) {  // a spatial split that clipping emptied: halve instead
    std::vector<BuildPrim>& all = left.empty() ? right : left;
    std::vector<BuildPrim> whole = std::move(all);
    left.assign(whole.begin(), whole.begin() + whole.size() / 2);
    right.assign(whole.begin() + whole.size() / 2, whole.end());
  }
  std::vector<BuildPrim>().swap(refs);
  for (const BuildPrim& r : left) lb.Extend(r.Bounds());
  for (const BuildPrim& r : right) rb.Extend(r.Bounds());
  lb = Clip(lb, bounds);
  rb = Clip(rb, bounds);
  double duplicates = double(left.size() + right.size()) - double(n);
  double rest = std::max(0.0, budget - duplicates);
  double share = double(left.size()) / double(left.size() + right.size());
  uint32_t l = Child(task, scratch, std::move(left), lb, depth + 1, rest * share);
  uint32_t r = Child(task, scratch, std::move(right), rb, depth + 1, rest * (1.0 - share));
  task.nodes[index].child[0] = l;
  task.nodes[index].child[1] = r;
  return index;
}

}  // namespace
}  // namespace bvh_internal

BvhBuildResult BuildSbvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                         int maxDepth, const PrimClipper& clip) {
  BvhBuildResult result;
  bvh_internal::SbvhBuilder builder(primBounds, options, maxDepth, clip);
  builder.Build(&result);
  return result;
}

}  // namespace pt
