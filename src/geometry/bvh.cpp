// Binned SAH build (object splits only), subtrees as parallel tasks, and the shared pieces of
// every builder: binning, partitioning, flattening the task tree.
#include "src/geometry/bvh.h"

#include <cmath>

#include "src/geometry/bvh_build_internal.h"

namespace pt {
namespace bvh_internal {

Split FindObjectSplit(const BuildPrim* prims, uint32_t n, const Aabb& centroidBounds,
                      int binCount, BinScratch& scratch, BinMapper mappers[3]) {
  std::fill(scratch.bins.begin(), scratch.bins.end(), Bin{});
  Bin* bins[3] = {&scratch.bins[0], &scratch.bins[binCount], &scratch.bins[2 * size_t(binCount)]};
  bool usable[3];
  for (int axis = 0; axis < 3; ++axis) {
    float extent = centroidBounds.hi[axis] - centroidBounds.lo[axis];
    usable[axis] = extent > 0.0f && std::isfinite(extent);
    mappers[axis] = {centroidBounds.lo[axis], usable[axis] ? binCount / extent : 0.0f, binCount};
  }
  for (uint32_t i = 0; i < n; ++i) {
    const BuildPrim& prim = prims[i];
    vec3 c = prim.Centroid();
    for (int axis = 0; axis < 3; ++axis) {
      Bin& bin = bins[axis][mappers[axis](c[axis])];
      bin.bounds.lo = detail::MinIgnoreNan(bin.bounds.lo, prim.lo);
      bin.bounds.hi = detail::MaxIgnoreNan(bin.bounds.hi, prim.hi);
      ++bin.count;
    }
  }
  // Sweep from the right, then from the left, scoring the plane after each bin. A plane after
  // an empty bin scores the same as the one before it, so areas are computed only where a bin
  // adds something (most bins of a small node are empty).
  Split best;
  std::vector<double>& rightCost = scratch.rightCost;
  std::vector<Aabb>& rightBounds = scratch.rightBounds;
  for (int axis = 0; axis < 3; ++axis) {
    if (!usable[axis]) continue;
    const Bin* b = bins[axis];
    Aabb acc;
    uint32_t count = 0;
    double cost = -1.0;
    for (int i = binCount - 1; i > 0; --i) {
      if (b[i].count > 0) {
        acc.Extend(b[i].bounds);
        count += b[i].count;
        cost = count * Area(acc);
      }
      rightCost[i] = cost;
      rightBounds[i] = acc;
    }
    acc = Aabb();
    count = 0;
    for (int i = 0; i < binCount - 1; ++i) {
      if (b[i].count == 0) continue;
      acc.Extend(b[i].bounds);
      count += b[i].count;
      if (rightCost[i + 1] < 0.0) break;  // nothing right of here
      double total = count * Area(acc) + rightCost[i + 1];
      if (best.axis < 0 || total < best.cost) best = {axis, i, total, acc, rightBounds[i + 1]};
    }
  }
  return best;
}

uint32_t PartitionObjects(BuildPrim* prims, uint32_t n, const Split& split, const BinMapper& mapper,
                          Aabb* leftCentroids, Aabb* rightCentroids) {
  int axis = split.axis, bin = split.bin;
  auto goesLeft = [&](const BuildPrim& p) { return mapper(p.Centroid(axis)) <= bin; };
  Aabb lc, rc;
  uint32_t i = 0, j = n;
  for (;;) {
    while (i < j && goesLeft(prims[i])) lc.Extend(prims[i++].Centroid());
    while (i < j && !goesLeft(prims[j - 1])) rc.Extend(prims[--j].Centroid());
    if (i >= j) break;
    std::swap(prims[i], prims[j - 1]);
    lc.Extend(prims[i++].Centroid());
    rc.Extend(prims[--j].Centroid());
  }
  *leftCentroids = lc;
  *rightCentroids = rc;
  return i;
}

namespace {

struct FlattenState {
  TaskRunner& runner;
  BvhBuildResult* out;
};

void Emit(FlattenState& st, uint32_t taskId, uint32_t local, uint32_t outIndex, int depth) {
  Task& task = st.runner.Get(taskId);
  const TaskNode& n = task.nodes[local];
  BvhNode& dst = st.out->nodes[outIndex];
  dst.boundsMin = n.bounds.lo;
  dst.boundsMax = n.bounds.hi;
  if (n.leaf) {
    dst.leftOrFirst = uint32_t(st.out->primOrder.size());
    dst.count = n.count;
    st.out->primOrder.insert(st.out->primOrder.end(), task.leafPrims.begin() + n.first,
                             task.leafPrims.begin() + n.first + n.count);
    st.out->maxDepth = std::max(st.out->maxDepth, depth);
    return;
  }
  uint32_t children = uint32_t(st.out->nodes.size());
  st.out->nodes.resize(children + 2);  // invalidates dst
  st.out->nodes[outIndex].leftOrFirst = children;
  st.out->nodes[outIndex].count = 0;
  uint32_t refs[2] = {n.child[0], n.child[1]};
  for (int k = 0; k < 2; ++k) {
    uint32_t ref = refs[k];
    if (ref & kTaskRef) Emit(st, ref & ~kTaskRef, 0, children + k, depth + 1);
    else Emit(st, taskId, ref, children + k, depth + 1);
  }
}

}  // namespace

void FlattenTasks(TaskRunner& runner, BvhBuildResult* out) {
  size_t nodes = 0, prims = 0;
  for (size_t i = 0; i < runner.Count(); ++i) {
    nodes += runner.Get(uint32_t(i)).nodes.size();
    prims += runner.Get(uint32_t(i)).leafPrims.size();
  }
  out->nodes.clear();
  out->nodes.reserve(nodes);
  out->primOrder.clear();
  out->primOrder.reserve(prims);
  out->maxDepth = 0;
  out->nodes.emplace_back();
  FlattenState st{runner, out};
  Emit(st, 0, 0, 0, 0);
}

int BuildThreads(int requested) {
  if (requested > 0) return requested;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

namespace {

// Binned SAH over a shared array of references, partitioned in place; subtrees of at least
// kMinTaskPrims references become tasks.
class SahBuilder {
 public:
  SahBuilder(const std::vector<Aabb>& bounds, const BvhBuildOptions& options, int maxDepth)
      : runner_(BuildThreads(options.threads)) {
    maxLeafSize_ = std::max(1, options.maxLeafSize);
    maxDepth_ = std::clamp(maxDepth, 0, kBvhMaxDepth);
    binCount_ = std::clamp(options.binCount, 2, kMaxBins);
    prims_.resize(bounds.size());
    for (size_t i = 0; i < bounds.size(); ++i) {
      prims_[i] = BuildPrim{bounds[i].lo, uint32_t(i), bounds[i].hi, 0};
    }
  }

  void Build(BvhBuildResult* out) {
    Task root;
    root.begin = 0;
    root.end = uint32_t(prims_.size());
    for (const BuildPrim& p : prims_) {
      root.bounds.Extend(p.Bounds());
      root.centroidBounds.Extend(p.Centroid());
    }
    runner_.Spawn(std::move(root));
    runner_.Run([&](Task& task) {
      BinScratch scratch(binCount_);
      Node(task, scratch, task.begin, task.end, task.bounds, task.centroidBounds, task.depth);
    });
    FlattenTasks(runner_, out);
  }

 private:
  uint32_t Node(Task& task, BinScratch& scratch, uint32_t begin, uint32_t end, const Aabb& bounds,
                const Aabb& centroids, int depth);
  uint32_t Child(Task& task, BinScratch& scratch, uint32_t begin, uint32_t end,
                 const Aabb& bounds, const Aabb& centroids, int depth) {
    if (end - begin < kMinTaskPrims || runner_.Threads() == 1)
      return Node(task, scratch, begin, end, bounds, centroids, depth);
    Task sub;
    sub.begin = begin;
    sub.end = end;
    sub.bounds = bounds;
    sub.centroidBounds = centroids;
    sub.depth = depth;
    return kTaskRef | runner_.Spawn(std::move(sub));
  }
  uint32_t Leaf(Task& task, uint32_t index, uint32_t begin, uint32_t end) {
    TaskNode& node = task.nodes[index];
    node.leaf = true;
    node.first = uint32_t(task.leafPrims.size());
    node.count = end - begin;
    for (uint32_t i = begin; i < end; ++i) task.leafPrims.push_back(prims_[i].index);
    return index;
  }

  TaskRunner runner_;
  std::vector<BuildPrim> prims_;
  int maxLeafSize_ = 4;
  int binCount_ = 16;
  int maxDepth_ = kBvhMaxDepth;
};

uint32_t SahBuilder::Node(Task& task, BinScratch& scratch, uint32_t begin, uint32_t end,
                          const Aabb& bounds, const Aabb& centroids, int depth) {
  uint32_t index = uint32_t(task.nodes.size());
  task.nodes.emplace_back();
  task.nodes[index].bounds = bounds;
  uint32_t n = end - begin;
  if (n <= 1 || depth >= maxDepth_) return Leaf(task, index, begin, end);

  BinMapper mappers[3];
  Split split = FindObjectSplit(&prims_[begin], n, centroids, binCount_, scratch, mappers);
  bool fits = n <= uint32_t(maxLeafSize_);
  uint32_t mid;
  Aabb lb, rb, lc, rc;
  if (split.axis < 0) {
    if (fits) return Leaf(task, index, begin, end);
    mid = begin + n / 2;  // identical centroids: the index order is as good as any
    for (uint32_t i = begin; i < end; ++i) {
      (i < mid ? lb : rb).Extend(prims_[i].Bounds());
      (i < mid ? lc : rc).Extend(prims_[i].Centroid());
    }
  } else {
    double area = Area(bounds);
    double splitCost = kTraversalCost + kIntersectCost * split.cost / area;
    if (fits && (!(area > 0.0) || !(splitCost < kIntersectCost * n))) {
      return Leaf(task, index, begin, end);
    }
    mid = begin + PartitionObjects(&prims_[begin], n, split, mappers[split.axis], &lc, &rc);
    lb = split.left;
    rb = split.right;
    if (mid == begin || mid == end) {  // unreachable: both sides counted
      mid = begin + n / 2;
      lb = rb = lc = rc = Aabb();
      for (uint32_t i = begin; i < end; ++i) {
        (i < mid ? lb : rb).Extend(prims_[i].Bounds());
        (i < mid ? lc : rc).Extend(prims_[i].Centroid());
      }
    }
  }
  uint32_t left = Child(task, scratch, begin, mid, lb, lc, depth + 1);  // depth <= kBvhMaxDepth
  uint32_t right = Child(task, scratch, mid, end, rb, rc, depth + 1);
  task.nodes[index].child[0] = left;
  task.nodes[index].child[1] = right;
  return index;
}

}  // namespace
}  // namespace bvh_internal

BvhBuildResult BuildSbvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                         int maxDepth, const PrimClipper& clip);

BvhBuildResult BuildBvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                        int maxDepth, const PrimClipper& clip) {
  BvhBuildResult result;
  if (primBounds.empty()) {  // an empty root: count 0 and empty bounds, which every ray misses
    result.nodes.push_back(BvhNode{});
    result.nodes[0].boundsMin = Aabb().lo;
    result.nodes[0].boundsMax = Aabb().hi;
    result.nodes[0].leftOrFirst = 0;
    result.nodes[0].count = 0;
    return result;
  }
  if (options.builder == BvhBuilder::kSbvh && clip) {
    return BuildSbvh(primBounds, options, maxDepth, clip);
  }
  bvh_internal::SahBuilder builder(primBounds, options, maxDepth);
  builder.Build(&result);
  return result;
}

double BinarySahCost(const std::vector<BvhNode>& nodes) {
  if (nodes.empty()) return 0.0;
  double rootArea = bvh_internal::Area(Aabb{nodes[0].boundsMin, nodes[0].boundsMax});
  if (!(rootArea > 0.0)) return 0.0;
  double cost = 0.0;
  for (const BvhNode& n : nodes) {
    double a = bvh_internal::Area(Aabb{n.boundsMin, n.boundsMax});
    cost += n.IsLeaf() ? bvh_internal::kIntersectCost * n.count * a
                       : bvh_internal::kTraversalCost * a;
  }
  return cost / rootArea;
}

}  // namespace pt
