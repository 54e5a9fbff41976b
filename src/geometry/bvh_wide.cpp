// Binary BVH -> 8-wide compressed BVH (Ylitie, Karras, Laine 2017, section 3).
#include "src/geometry/bvh_wide.h"

#include "src/geometry/bvh_build_internal.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace pt {
namespace {

constexpr int kWidth = 8;
constexpr uint32_t kMaxLeafPrims = 3;
// The collapse's cost model (the paper's): one node visit 1, one primitive test 0.3.
constexpr float kNodeCost = 1.0f;
constexpr float kPrimCost = 0.3f;

float AreaF(const Aabb& b) {
  if (b.IsEmpty()) return 0.0f;
  vec3 d = b.hi - b.lo;
  return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

Aabb NodeBox(const BvhNode& n) { return Aabb{n.boundsMin, n.boundsMax}; }

Aabb Intersect(const Aabb& a, const Aabb& b) {
  return Aabb{glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}

// A copy of the binary tree whose leaves hold at most kMaxLeafPrims primitives: bigger leaves
// (the depth cap, or a builder asked for bigger leaves) become balanced subtrees. Leaf ranges
// still index the binary primOrder.
class LeafSplitter {
 public:
  LeafSplitter(const BvhBuildResult& b, const std::vector<Aabb>& bounds, uint32_t maxLeafPrims)
      : b_(b), bounds_(bounds), maxLeafPrims_(maxLeafPrims) {}
  std::vector<BvhNode> Run() {
    out_.reserve(b_.nodes.size() + b_.nodes.size() / 8);
    out_.emplace_back();
    Copy(0, 0);
    return std::move(out_);
  }

 private:
  void Copy(uint32_t src, uint32_t dst) {
    const BvhNode n = b_.nodes[src];
    if (n.IsLeaf()) {
      if (n.count <= maxLeafPrims_) out_[dst] = n;
      else SplitRange(n.leftOrFirst, n.count, NodeBox(n), dst);
      return;
    }
    uint32_t c = uint32_t(out_.size());
    out_.resize(c + 2);
    out_[dst] = n;
    out_[dst].leftOrFirst = c;
    Copy(n.leftOrFirst, c);
    Copy(n.leftOrFirst + 1, c + 1);
  }
  // With spatial splits a reference's bounds exceed the part the leaf holds: clip to the leaf.
  void SplitRange(uint32_t first, uint32_t count, const Aabb& leafBox, uint32_t dst) {
    Aabb box;
    for (uint32_t i = first; i < first + count; ++i) box.Extend(bounds_[b_.primOrder[i]]);
    box = Intersect(box, leafBox);
    out_[dst].boundsMin = box.lo;
    out_[dst].boundsMax = box.hi;
    if (count <= maxLeafPrims_) {
      out_[dst].leftOrFirst = first;
      out_[dst].count = count;
      return;
    }
    uint32_t c = uint32_t(out_.size());
    out_.resize(c + 2);
    out_[dst].leftOrFirst = c;
    out_[dst].count = 0;
    uint32_t half = count / 2;
    SplitRange(first, half, leafBox, c);
    SplitRange(first + half, count - half, leafBox, c + 1);
  }

  const BvhBuildResult& b_;
  const std::vector<Aabb>& bounds_;
  uint32_t maxLeafPrims_;
  std::vector<BvhNode> out_;
};

// ---- Conservative quantisation ----

// x - origin as an unevaluated sum d + err of doubles (Knuth's TwoSum), exact.
void ExactDifference(float x, float origin, double* d, double* err) {
  double a = x, b = -double(origin);
  double s = a + b;
  double bb = s - a;
  *d = s;
  *err = (a - (s - bb)) + (b - bb);
}

// Largest q >= 0 with origin + q * scale <= x in real arithmetic (origin <= x).
int QuantizeDown(float x, float origin, double scale) {
  double d, err;
  ExactDifference(x, origin, &d, &err);
  double q = std::floor(d / scale);  // division by a power of two: exact
  if (err < 0.0 && q * scale == d) q -= 1.0;
  return q < 0.0 ? 0 : int(std::min(q, 255.0));
}

// Smallest q with origin + q * scale >= x in real arithmetic; may exceed 255.
int QuantizeUp(float x, float origin, double scale) {
  double d, err;
  ExactDifference(x, origin, &d, &err);
  double q = std::ceil(d / scale);
  if (err > 0.0 && q * scale == d) q += 1.0;
  return q < 0.0 ? 0 : int(std::min(q, 1024.0));
}

float Finite(float v) { return std::isfinite(v) ? v : (v > 0.0f ? FLT_MAX : -FLT_MAX); }

// Fills origin, exponents and the boxes of the used slots of `node`; unused slots get an
// inverted box (and meta 0, set by the caller), which no ray hits.
void Quantize(const Aabb boxes[kWidth], const bool used[kWidth], WideBvhNode* node) {
  Aabb all;
  Aabb fin[kWidth];
  for (int i = 0; i < kWidth; ++i) {
    if (!used[i]) continue;
    fin[i] = Aabb{vec3(Finite(boxes[i].lo.x), Finite(boxes[i].lo.y), Finite(boxes[i].lo.z)),
                  vec3(Finite(boxes[i].hi.x), Finite(boxes[i].hi.y), Finite(boxes[i].hi.z))};
    all.Extend(fin[i]);
  }
  node->origin = all.lo;
  for (int axis = 0; axis < 3; ++axis) {
    float lo = all.lo[axis], hi = all.hi[axis];
    double extent = double(hi) - double(lo);
    int k = extent > 0.0 ? int(std::ceil(std::log2(extent / 255.0))) : -126;
    k = std::clamp(k, -126, 127);
    for (;; ++k) {  // rounding of log2 may leave the top bound one step out of reach
      double scale = std::ldexp(1.0, k);
      bool fits = true;
      for (int i = 0; i < kWidth && fits; ++i)
        fits = !used[i] || QuantizeUp(fin[i].hi[axis], lo, scale) <= 255;
      if (fits || k == 127) break;
    }
    double scale = std::ldexp(1.0, k);
    node->exponent[axis] = uint8_t(k + 127);
    for (int i = 0; i < kWidth; ++i) {
      node->qlo[axis][i] = used[i] ? uint8_t(QuantizeDown(fin[i].lo[axis], lo, scale)) : 255;
      node->qhi[axis][i] = used[i] ? uint8_t(std::min(QuantizeUp(fin[i].hi[axis], lo, scale), 255)) : 0;
    }
  }
}

// ---- The collapse ----

// Binary subtrees of at most this many primitives are collapsed as independent tasks (cost
// pass and emission), on as many threads as the build has. Larger ones are done first, on one
// thread; smaller ones inline. Fixed counts, so the layout never depends on the thread count.
constexpr uint32_t kTaskPrims = 4096;
constexpr uint32_t kMinTaskPrims = 64;

// Runs fn(i) for i in [0, count) on `threads` threads; the first exception is rethrown.
template <typename Fn>
void ForEachParallel(size_t count, int threads, const Fn& fn) {
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex errorMutex;
  auto worker = [&] {
    for (size_t i; (i = next.fetch_add(1)) < count;) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(errorMutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < std::min(size_t(std::max(threads, 1)), count); ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Wide nodes and primitive slots as one emission writes them.
struct WideOut {
  std::vector<WideBvhNode> nodes;
  std::vector<uint32_t> primOrder;
  double sah = 0.0;
  int maxDepth = 0;
};

// A wide node whose subtree is emitted as a task: its slot, binary node and depth.
struct Deferred {
  uint32_t wideIndex;
  uint32_t binary;
  int depth;
};

class Collapser {
 public:
  Collapser(const BvhBuildResult& binary, const std::vector<BvhNode>& nodes, int threads,
            uint32_t maxLeafPrims)
      : binary_(binary), nodes_(nodes), threads_(threads), maxLeafPrims_(maxLeafPrims) {}

  void Run(WideBvhResult* result) {
    ComputeCosts();
    WideOut top;
    top.nodes.reserve(nodes_.size() / 3 + 1);
    top.primOrder.reserve(binary_.primOrder.size());
    top.nodes.emplace_back();
    std::vector<uint32_t> children;
    if (nodes_[0].IsLeaf()) children.push_back(0);  // a root leaf: one leaf slot
    else Gather(0, 0, children);
    std::vector<Deferred> deferred;
    Emit(top, 0, children, 0, &deferred);
    std::vector<WideOut> parts(deferred.size());
    ForEachParallel(deferred.size(), threads_, [&](size_t i) {
      std::vector<uint32_t> grand;
      Gather(deferred[i].binary, 0, grand);
      parts[i].nodes.emplace_back();
      Emit(parts[i], 0, grand, deferred[i].depth, nullptr);
    });
    for (size_t i = 0; i < parts.size(); ++i) Append(parts[i], deferred[i].wideIndex, &top);
    float rootArea = AreaF(NodeBox(nodes_[0]));
    result->nodes = std::move(top.nodes);
    result->primOrder = std::move(top.primOrder);
    result->maxDepth = top.maxDepth;
    result->sahCost = rootArea > 0.0f ? top.sah / rootArea : 0.0;
  }

 private:
  float& Cost(uint32_t n, int slots) { return cost_[size_t(n) * kWidth + slots - 1]; }
  int8_t& Choice(uint32_t n, int slots) { return choice_[size_t(n) * kWidth + slots - 1]; }

  void ComputeCosts();
  void NodeCost(uint32_t i);
  // Appends the binary nodes that become the slots when `n`'s children share the node's 8
  // slots (slotsFor = 0: as the DP's best internal split of n), or n spread over `slotsFor`.
  void Gather(uint32_t n, int slotsFor, std::vector<uint32_t>& out);
  // Writes the wide node `wideIndex` over `children` and, depth-first, its interior children;
  // with `deferred`, subtrees of task size are left to tasks instead.
  void Emit(WideOut& out, uint32_t wideIndex, const std::vector<uint32_t>& children, int depth,
            std::vector<Deferred>* deferred);
  void AssignSlots(const std::vector<uint32_t>& children, int slotOf[kWidth]);
  static void Append(const WideOut& part, uint32_t wideIndex, WideOut* top);
  void LeafPrims(uint32_t n, std::vector<uint32_t>& out) {
    const BvhNode& b = nodes_[n];
    if (b.IsLeaf()) {
      for (uint32_t i = 0; i < b.count; ++i) out.push_back(binary_.primOrder[b.leftOrFirst + i]);
      return;
    }
    LeafPrims(b.leftOrFirst, out);
    LeafPrims(b.leftOrFirst + 1, out);
  }
  bool Interior(uint32_t i) const { return !nodes_[i].IsLeaf() && nodes_[i].leftOrFirst != 0; }

  // Per-node tables, left uninitialised (every entry is written before it is read): zeroing
  // them was a fifth of the collapse of a 1M-triangle mesh, in page faults on one thread.
  template <typename T>
  using Table = std::unique_ptr<T[]>;

  const BvhBuildResult& binary_;
  const std::vector<BvhNode>& nodes_;
  int threads_;
  uint32_t maxLeafPrims_;
  Table<float> cost_;     // [node][slots - 1]: best cost of the subtree over that many slots
  Table<int8_t> choice_;  // 0: one slot; -1: as with one slot fewer; k: k slots go left
  Table<int8_t> split8_;  // k of the best distribution of the 8 slots over the children
  Table<uint8_t> asLeaf_;  // one slot: a leaf (1) or a node (0)
  Table<uint32_t> primCount_;
  Table<uint32_t> last_;  // last descendant (descendants are [leftOrFirst, last_])
};

// Every node's cost depends on its children's only, and a node's descendants are one index
// range after it: so subtrees of task size are costed in parallel, then the nodes above them.
void Collapser::ComputeCosts() {
  size_t n = nodes_.size();
  cost_.reset(new float[n * kWidth]);
  choice_.reset(new int8_t[n * kWidth]);
  split8_.reset(new int8_t[n]);
  asLeaf_.reset(new uint8_t[n]);
  primCount_.reset(new uint32_t[n]);
  last_.reset(new uint32_t[n]);
  for (size_t idx = n; idx-- > 0;) {  // children always follow their parent
    uint32_t i = uint32_t(idx), l = nodes_[i].leftOrFirst;
    primCount_[i] = Interior(i) ? primCount_[l] + primCount_[l + 1] : nodes_[i].count;
    last_[i] = Interior(i) ? std::max(last_[l], last_[l + 1]) : i;
  }
  std::vector<uint32_t> tasks, above, todo{0};
  while (!todo.empty()) {
    uint32_t i = todo.back();
    todo.pop_back();
    if (!Interior(i) || primCount_[i] <= kTaskPrims) {
      tasks.push_back(i);
      continue;
    }
    above.push_back(i);
    todo.push_back(nodes_[i].leftOrFirst);
    todo.push_back(nodes_[i].leftOrFirst + 1);
  }
  ForEachParallel(tasks.size(), threads_, [&](size_t t) {
    const uint32_t root = tasks[t];  // its descendants, deepest first, then itself
    if (Interior(root)) {
      for (uint32_t i = last_[root] + 1; i-- > nodes_[root].leftOrFirst;) NodeCost(i);
    }
    NodeCost(root);
  });
  std::sort(above.begin(), above.end());
  for (size_t k = above.size(); k-- > 0;) NodeCost(above[k]);
}

void Collapser::NodeCost(uint32_t i) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const BvhNode& node = nodes_[i];
  float area = AreaF(NodeBox(node));
  if (!Interior(i)) {
    float leaf = area * kPrimCost * float(node.count);
    for (int s = 1; s <= kWidth; ++s) {
      Cost(i, s) = leaf;
      Choice(i, s) = s == 1 ? 0 : -1;
    }
    asLeaf_[i] = 1;
    split8_[i] = 0;
    return;
  }
  uint32_t l = node.leftOrFirst, r = l + 1;
  float dist[kWidth + 1];
  int8_t arg[kWidth + 1];
  for (int j = 2; j <= kWidth; ++j) {
    dist[j] = kInf;
    arg[j] = 1;
    for (int k = 1; k < j; ++k) {
      float c = Cost(l, k) + Cost(r, j - k);
      if (c < dist[j]) dist[j] = c, arg[j] = int8_t(k);
    }
  }
  float leaf = primCount_[i] <= maxLeafPrims_ ? area * kPrimCost * float(primCount_[i]) : kInf;
  float internal = dist[kWidth] + area * kNodeCost;
  split8_[i] = arg[kWidth];
  asLeaf_[i] = leaf <= internal ? 1 : 0;
  Cost(i, 1) = std::min(leaf, internal);
  Choice(i, 1) = 0;
  for (int s = 2; s <= kWidth; ++s) {
    bool distribute = dist[s] < Cost(i, s - 1);
    Cost(i, s) = distribute ? dist[s] : Cost(i, s - 1);
    Choice(i, s) = distribute ? arg[s] : -1;
  }
}

void Collapser::Gather(uint32_t n, int slots, std::vector<uint32_t>& out) {
  const BvhNode& node = nodes_[n];
  int left;
  if (slots == 0) {
    left = split8_[n];
    slots = kWidth;
  } else {
    while (Choice(n, slots) == -1) --slots;
    if (Choice(n, slots) == 0) {
      out.push_back(n);
      return;
    }
    left = Choice(n, slots);
  }
  Gather(node.leftOrFirst, left, out);
  Gather(node.leftOrFirst + 1, slots - left, out);
}

// Greedy matching of children to slots: slot s is the child met first by rays whose
// direction has the signs of octant s (bit a set: negative along axis a), i.e. the smallest
// centroid projection on that octant's diagonal (the paper's cost table, solved greedily).
void Collapser::AssignSlots(const std::vector<uint32_t>& children, int slotOf[kWidth]) {
  int count = int(children.size());
  Aabb parent;
  vec3 centroid[kWidth];
  for (int c = 0; c < count; ++c) {
    Aabb box = NodeBox(nodes_[children[c]]);
    centroid[c] = box.Centroid();
    parent.Extend(box);
  }
  float cost[kWidth][kWidth];
  for (int c = 0; c < count; ++c) {
    vec3 rel = centroid[c] - parent.Centroid();
    for (int s = 0; s < kWidth; ++s) {
      vec3 dir((s & 1) ? -1.0f : 1.0f, (s & 2) ? -1.0f : 1.0f, (s & 4) ? -1.0f : 1.0f);
      cost[c][s] = glm::dot(rel, dir);
    }
  }
  bool slotUsed[kWidth] = {};
  for (int c = 0; c < count; ++c) slotOf[c] = -1;
  for (int round = 0; round < count; ++round) {
    int bc = -1, bs = -1;
    for (int c = 0; c < count; ++c) {
      if (slotOf[c] >= 0) continue;
      for (int s = 0; s < kWidth; ++s) {
        if (!slotUsed[s] && (bc < 0 || cost[c][s] < cost[bc][bs])) bc = c, bs = s;
      }
    }
    slotOf[bc] = bs;
    slotUsed[bs] = true;
  }
}

void Collapser::Emit(WideOut& out, uint32_t wideIndex, const std::vector<uint32_t>& children,
                     int depth, std::vector<Deferred>* deferred) {
  if (depth >= kWideStackSize) throw std::logic_error("wide BVH deeper than its stack");
  out.maxDepth = std::max(out.maxDepth, depth);
  int slotOf[kWidth];
  AssignSlots(children, slotOf);
  int childAt[kWidth];  // slot -> index into children, or -1
  for (int s = 0; s < kWidth; ++s) childAt[s] = -1;
  for (int c = 0; c < int(children.size()); ++c) childAt[slotOf[c]] = c;

  WideBvhNode node{};
  node.childBase = uint32_t(out.nodes.size());
  node.primBase = uint32_t(out.primOrder.size());
  Aabb boxes[kWidth], all;
  bool used[kWidth];
  uint32_t interior[kWidth];
  int interiorCount = 0;
  for (int s = 0; s < kWidth; ++s) {
    used[s] = childAt[s] >= 0;
    if (!used[s]) continue;
    uint32_t b = children[childAt[s]];
    boxes[s] = NodeBox(nodes_[b]);
    all.Extend(boxes[s]);
    if (asLeaf_[b]) {  // the subtree's primitives (at most 3) at primBase + offset (< 24)
      uint32_t offset = uint32_t(out.primOrder.size()) - node.primBase;
      size_t before = out.primOrder.size();
      LeafPrims(b, out.primOrder);
      uint32_t n = uint32_t(out.primOrder.size() - before);
      node.meta[s] = uint8_t((((1u << n) - 1u) << 5) | offset);
      out.sah += double(AreaF(boxes[s])) * kPrimCost * n;
    } else {
      node.innerMask |= uint8_t(1u << s);
      node.meta[s] = uint8_t((1u << 5) | (24u + uint32_t(s)));
      interior[interiorCount++] = b;
    }
  }
  out.sah += double(AreaF(all)) * kNodeCost;
  Quantize(boxes, used, &node);
  out.nodes.resize(out.nodes.size() + interiorCount);
  out.nodes[wideIndex] = node;
  // Interior children fill the block at childBase in slot order, each depth-first.
  std::vector<uint32_t> grand;
  for (int i = 0; i < interiorCount; ++i) {
    uint32_t prims = primCount_[interior[i]];
    if (deferred && prims <= kTaskPrims && prims > kMinTaskPrims) {
      deferred->push_back(Deferred{node.childBase + uint32_t(i), interior[i], depth + 1});
      continue;
    }
    grand.clear();
    Gather(interior[i], 0, grand);
    Emit(out, node.childBase + uint32_t(i), grand, depth + 1, deferred);
  }
}

// A task's subtree (its root at part.nodes[0]) into the slot reserved for it, the rest
// appended, with node and primitive indices moved to where they now live.
void Collapser::Append(const WideOut& part, uint32_t wideIndex, WideOut* top) {
  const uint32_t nodeShift = uint32_t(top->nodes.size()) - 1u;
  const uint32_t primShift = uint32_t(top->primOrder.size());
  for (size_t k = 0; k < part.nodes.size(); ++k) {
    WideBvhNode node = part.nodes[k];
    node.childBase += nodeShift;
    node.primBase += primShift;
    if (k == 0) top->nodes[wideIndex] = node;
    else top->nodes.push_back(node);
  }
  top->primOrder.insert(top->primOrder.end(), part.primOrder.begin(), part.primOrder.end());
  top->sah += part.sah;
  top->maxDepth = std::max(top->maxDepth, part.maxDepth);
}

}  // namespace

WideBvhResult CollapseToWide(const BvhBuildResult& binary, const std::vector<Aabb>& primBounds,
                             int threads, int maxLeafPrims) {
  const uint32_t leafLimit = uint32_t(std::clamp(maxLeafPrims, 1, int(kMaxLeafPrims)));
  WideBvhResult result;
  if (binary.nodes.empty() || binary.primOrder.empty()) return result;
  // Leaves of more than 3 primitives (the depth cap, or another leaf size) are split in a copy;
  // without any, that copy would be the same nodes in the same order.
  bool bigLeaves = false;
  for (const BvhNode& n : binary.nodes) bigLeaves = bigLeaves || (n.IsLeaf() && n.count > leafLimit);
  std::vector<BvhNode> split;
  if (bigLeaves) split = LeafSplitter(binary, primBounds, leafLimit).Run();
  Collapser(binary, bigLeaves ? split : binary.nodes, bvh_internal::BuildThreads(threads),
            leafLimit)
      .Run(&result);
  return result;
}

}  // namespace pt
