// Internals shared by the BVH builders (bvh.cpp: binned SAH, bvh_sbvh.cpp: spatial splits):
// the primitive record they move around, SAH binning, and the task tree that lets subtrees be
// built on several threads and flattened afterwards in an order that does not depend on timing.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "src/geometry/bvh.h"

namespace pt::bvh_internal {

// SAH costs relative to one primitive test. A GPU pays more for a node (a divergent 64-byte
// fetch of both children) than pbrt-v4's 1/2 assumes: with 1, leaves of a 270k-triangle mesh
// hold ~1.7 primitives instead of ~1, for 17% fewer nodes and the same nodes visited per ray.
constexpr double kTraversalCost = 1.0;
constexpr double kIntersectCost = 1.0;
constexpr int kMaxBins = 256;
// Subtrees of at least this many primitives become tasks that another thread may take.
constexpr uint32_t kMinTaskPrims = 8192;

// Areas in double: scenes up to 1e19 units across would overflow a float area.
inline double Area(const Aabb& b) {
  if (b.IsEmpty()) return 0.0;
  double dx = double(b.hi.x) - b.lo.x, dy = double(b.hi.y) - b.lo.y, dz = double(b.hi.z) - b.lo.z;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}

// One primitive reference as the builder moves it around: bounds and input index in 32 bytes,
// permuted in place so every pass reads memory in order (indexing a bounds array through a
// shuffled permutation made the build cache-miss bound, ~10x slower at 270k primitives).
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
  Aabb left, right;   // bounds of the two sides (unions of their bins)
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

// Per-thread scratch of the binned object-split search.
struct BinScratch {
  std::vector<Bin> bins;          // binCount bins per axis
  std::vector<double> rightCost;  // cost of the right side of each plane
  std::vector<Aabb> rightBounds;
  explicit BinScratch(int binCount)
      : bins(3 * size_t(binCount)), rightCost(binCount), rightBounds(binCount) {}
};

// Best binned object split of prims[0, n) whose centroids span centroidBounds; fills mappers.
Split FindObjectSplit(const BuildPrim* prims, uint32_t n, const Aabb& centroidBounds,
                      int binCount, BinScratch& scratch, BinMapper mappers[3]);

// Partitions prims[0, n) by the split's plane; returns the left count, and the centroid bounds
// of both sides. Falls back to the middle when a side would be empty (cannot happen for a
// split FindObjectSplit returned).
uint32_t PartitionObjects(BuildPrim* prims, uint32_t n, const Split& split, const BinMapper& mapper,
                          Aabb* leftCentroids, Aabb* rightCentroids);

// ---- Task tree ----

// A node as a task builds it. Interior: child[] are references, either a local index or
// kTaskRef | task id (a subtree built by another task). Leaf: prims [first, first + count) of
// the task's leaf list.
constexpr uint32_t kTaskRef = 0x80000000u;
struct TaskNode {
  Aabb bounds;
  uint32_t child[2] = {0, 0};
  uint32_t first = 0, count = 0;
  bool leaf = false;
};

struct Task {
  std::vector<BuildPrim> refs;  // SBVH: the task's own references; SAH: empty (shared array)
  uint32_t begin = 0, end = 0;  // SAH: range in the shared array
  Aabb bounds, centroidBounds;
  int depth = 0;
  double budget = 0.0;              // SBVH: duplicate references this subtree may still add
  std::vector<TaskNode> nodes;      // [0] is the subtree's root
  std::vector<uint32_t> leafPrims;  // input indices, leaf by leaf
};

// Runs tasks on a fixed number of threads until none is left; tasks may spawn tasks.
class TaskRunner {
 public:
  explicit TaskRunner(int threads) : threads_(std::max(1, threads)) {}
  // Adds a task; returns its id. Thread-safe.
  uint32_t Spawn(Task task);
  // Runs body(task) for the first task and every task spawned meanwhile, on the threads.
  template <typename Body>
  void Run(const Body& body);
  Task& Get(uint32_t id) { return tasks_[id]; }  // stable: a deque never moves elements
  size_t Count() const { return tasks_.size(); }
  int Threads() const { return threads_; }

 private:
  int threads_;
  std::deque<Task> tasks_;
  std::vector<uint32_t> ready_;
  uint32_t outstanding_ = 0;
  std::mutex mutex_;
  std::condition_variable cv_;
};

// Flattens the task tree into the binary layout (siblings adjacent, leaves in depth-first
// order) and the leaf primitive order.
void FlattenTasks(TaskRunner& runner, BvhBuildResult* out);

int BuildThreads(int requested);

}  // namespace pt::bvh_internal

namespace pt::bvh_internal {

inline uint32_t TaskRunner::Spawn(Task task) {
  std::lock_guard<std::mutex> lock(mutex_);
  uint32_t id = uint32_t(tasks_.size());
  tasks_.push_back(std::move(task));
  ready_.push_back(id);
  ++outstanding_;
  cv_.notify_one();
  return id;
}

template <typename Body>
void TaskRunner::Run(const Body& body) {
  auto worker = [&] {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      cv_.wait(lock, [&] { return !ready_.empty() || outstanding_ == 0; });
      if (ready_.empty()) return;  // nothing left anywhere
      uint32_t id = ready_.back();  // newest first: depth-first, the working set stays small
      ready_.pop_back();
      Task& task = tasks_[id];
      lock.unlock();
      body(task);
      lock.lock();
      if (--outstanding_ == 0) cv_.notify_all();
    }
  };
  std::vector<std::thread> threads;
  for (int i = 1; i < threads_; ++i) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
}

}  // namespace pt::bvh_internal
