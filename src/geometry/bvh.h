// Host-side BVH construction: binned SAH over primitive centroids (Wald 2007), optionally with
// spatial splits (SBVH, Stich et al. 2009), built by parallel subtree tasks; producing the flat
// BvhNode layout that traverse.h walks, which bvh_wide.h collapses into the wide layout.
#pragma once

#include <functional>
#include <vector>

#include "src/geometry/aabb.h"
#include "src/geometry/traverse_binary.h"
#include "src/scene/scene.h"

namespace pt {

struct BvhBuildResult {
  // Root at 0; an interior node's children are adjacent (leftOrFirst and leftOrFirst + 1);
  // a leaf covers primOrder[leftOrFirst, leftOrFirst + count).
  std::vector<BvhNode> nodes;
  // Leaf order: primOrder[i] is the input index of the i-th primitive in the leaves, so the
  // caller stores its PrimRefs in this order. With spatial splits an input index can appear in
  // several leaves (each time with the part of its bounds that the leaf holds).
  std::vector<uint32_t> primOrder;
  int maxDepth = 0;  // deepest leaf (root = 0), never above kBvhMaxDepth
};

// Bounds of the part of primitive `prim` inside `box` (a subset of both; empty if none). Spatial
// splits need it; a box-only clipper (Intersect of the bounds with box) is valid but weaker.
using PrimClipper = std::function<Aabb(uint32_t prim, const Aabb& box)>;

// Leaves hold at most options.maxLeafSize primitives (a node is split until it fits; among
// nodes that fit, SAH chooses between leaf and split), except at depth maxDepth (clamped to
// [0, kBvhMaxDepth]; only tests lower it), which is always a leaf. All centroids equal: split in
// the middle of the index range. No primitives: one root with count 0 and empty bounds
// (traversal reports no hit). Bounds are expected to be finite (the caller drops degenerate
// primitives); NaN or infinite ones do not crash the build but may give a poor tree.
// options.builder kSbvh needs `clip` (without one it builds plain SAH). Subtrees are built on
// options.threads threads (0 = all cores). Deterministic: the same input gives the same tree
// whatever the thread count.
BvhBuildResult BuildBvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                        int maxDepth = kBvhMaxDepth, const PrimClipper& clip = nullptr);

// SAH cost of a binary tree relative to one primitive test (node cost 1, primitive cost 1, as the
// builder weighs them), normalised by the root's area: what the builder minimises.
double BinarySahCost(const std::vector<BvhNode>& nodes);

}  // namespace pt
