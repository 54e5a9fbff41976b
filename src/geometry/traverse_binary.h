// Binary BVH traversal, and what every layout's traversal shares.
//
// One single-level traversal per node layout, generic over what a leaf holds: the traversal
// walks nodes and calls a leaf callback with each leaf's primitive range; the callback tests
// what the range names (scene primitives, or instances whose own BVH it traverses in turn)
// and may lower tMax. So a two-level structure is an outer traversal whose leaf callback
// transforms the ray and runs an inner traversal.
//
// Leaf callback contract (any callable):
//   bool leaf(uint32_t first, uint32_t count, float* tMax)
// called with the leaf's range [first, first + count) in the BVH's primitive order. It returns
// true when it accepted a hit (and then, for TraceMode::kClosest, has lowered *tMax to it);
// in TraceMode::kAny the traversal stops at the first true. Nodes farther than *tMax are culled.
// The traversal counts the nodes it enters into counters->nodes (counters may be nullptr);
// counting primitives is the callback's business (PrimLeaf does it).
#pragma once

#include "src/core/ray.h"
#include "src/geometry/aabb.h"
#include "src/geometry/interaction.h"
#include "src/scene/scene_view.h"

namespace pt {

// Deepest leaf BuildBvh makes (root = depth 0); a node deeper than this becomes a leaf whatever
// its size. Traversal pushes at most one sibling per ancestor of the node it is on, so the stack
// never holds more than kBvhMaxDepth entries. SAH trees of a few million primitives are ~30-45
// deep; only pathological inputs (e.g. geometrically spaced primitives) reach the cap.
constexpr int kBvhMaxDepth = 64;
constexpr int kBvhStackSize = kBvhMaxDepth;

enum class TraceMode { kClosest, kAny };

// Rays with a NaN or infinite component are rejected before any node is read (they would
// otherwise pass every slab test that ignores NaN, and walk the whole tree for nothing).
PT_HDI bool TraceableRay(const Ray& ray) { return IsFinite(ray.o) && IsFinite(ray.d); }

// The binary layout: a flat array of BvhNode, root at 0, children adjacent.
struct BinaryBvh {
  const BvhNode* nodes = nullptr;
  uint32_t nodeCount = 0;
};

PT_HDI BinaryBvh SceneBinaryBvh(const SceneView& s) { return BinaryBvh{s.nodes, s.nodeCount}; }

namespace detail {

// The step at an interior node whose children are nodes[left] and nodes[left + 1]: the nearer
// child the ray enters within tMax becomes *node and, when it enters both, the farther goes to
// push(child, entry distance). False when it enters neither.
template <typename PushFn>
PT_HDI_HOT bool StepIntoChildren(const BvhNode* nodes, uint32_t left, const vec3& o,
                                 const vec3& invDir, float tMax, uint32_t* node, PushFn& push) {
  const BvhNode& l = nodes[left];
  const BvhNode& r = nodes[left + 1];
  float tl = 0.0f, tr = 0.0f;  // read only where their test hit (and set them)
  const bool hitL = IntersectAabb(l.boundsMin, l.boundsMax, o, invDir, tMax, &tl);
  const bool hitR = IntersectAabb(r.boundsMin, r.boundsMax, o, invDir, tMax, &tr);
  if (hitL && hitR) {
    const bool leftFirst = tl <= tr;
    push(leftFirst ? left + 1 : left, leftFirst ? tr : tl);
    *node = leftFirst ? left : left + 1;
    return true;
  }
  if (!hitL && !hitR) return false;
  *node = hitL ? left : left + 1;
  return true;
}

}  // namespace detail

// Walks a binary BVH front to back (nearer child first) with a fixed-size stack (no allocation,
// no recursion). *tMax is the ray's extent on entry and the callback's last lowering on return.
template <TraceMode kMode, typename LeafFn>
PT_HDI void Traverse(const BinaryBvh& bvh, const Ray& ray, float* tMaxInOut, LeafFn& leaf,
                     TraversalCounters* counters) {
  if (bvh.nodeCount == 0 || !TraceableRay(ray)) return;
  float tMax = *tMaxInOut;
  const vec3 invDir(1.0f / ray.d.x, 1.0f / ray.d.y, 1.0f / ray.d.z);
  uint32_t nodesVisited = 0;

  // Entry distances travel with the stacked nodes so that a node farther than a hit found
  // meanwhile is skipped without reloading it.
  uint32_t stackNode[kBvhStackSize];
  float stackT[kBvhStackSize];
  int stackSize = 0;

  uint32_t node = 0;
  float tEntry;
  const BvhNode* nodes = bvh.nodes;
  bool active = IntersectAabb(nodes[0].boundsMin, nodes[0].boundsMax, ray.o, invDir, tMax, &tEntry);
  while (active) {
    ++nodesVisited;
    const BvhNode& n = nodes[node];
    if (n.IsLeaf()) {
      if (leaf(n.leftOrFirst, n.count, &tMax) && kMode == TraceMode::kAny) break;
    } else if (n.count == 0 && n.leftOrFirst != 0) {  // interior (a 0-count root is empty)
      auto push = [&](uint32_t child, float t) {
        if (stackSize < kBvhStackSize) {  // always true for BuildBvh's trees (see above)
          stackNode[stackSize] = child;
          stackT[stackSize] = t;
          ++stackSize;
        }
      };
      if (detail::StepIntoChildren(nodes, n.leftOrFirst, ray.o, invDir, tMax, &node, push)) continue;
    }
    // Pop the nearest pending node that may still hold something closer than tMax.
    active = false;
    while (stackSize > 0) {
      --stackSize;
      if (stackT[stackSize] <= tMax * kAabbFarScale) {  // as IntersectAabb culls
        node = stackNode[stackSize];
        active = true;
        break;
      }
    }
  }
  *tMaxInOut = tMax;
  if (counters) counters->nodes += nodesVisited;
}

}  // namespace pt
