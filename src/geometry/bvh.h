// Host-side BVH construction: binned SAH over primitive centroids (Wald 2007), producing the
// flat BvhNode layout that traverse.h walks.
#pragma once

#include <vector>

#include "src/geometry/aabb.h"
#include "src/geometry/traverse.h"
#include "src/scene/scene.h"

namespace pt {

struct BvhBuildResult {
  // Root at 0; an interior node's children are adjacent (leftOrFirst and leftOrFirst + 1);
  // a leaf covers primOrder[leftOrFirst, leftOrFirst + count).
  std::vector<BvhNode> nodes;
  // Leaf order: primOrder[i] is the input index of the i-th primitive in the leaves, so the
  // caller stores its PrimRefs in this order.
  std::vector<uint32_t> primOrder;
  int maxDepth = 0;  // deepest leaf (root = 0), never above kBvhMaxDepth
};

// Leaves hold at most options.maxLeafSize primitives (a node is split until it fits; among
// nodes that fit, SAH chooses between leaf and split), except at depth maxDepth (clamped to
// [0, kBvhMaxDepth]; only tests lower it), which is always a leaf. All centroids equal: split in
// the middle of the index range. No primitives: one root with count 0 and empty bounds
// (traversal reports no hit). Bounds are expected to be finite (the caller drops degenerate
// primitives); NaN or infinite ones do not crash the build but may give a poor tree.
// Deterministic: the same input gives the same tree.
BvhBuildResult BuildBvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                        int maxDepth = kBvhMaxDepth);

}  // namespace pt
