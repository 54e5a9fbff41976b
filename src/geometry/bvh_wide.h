// Host-side construction of the wide layout: a binary BVH collapsed into 8-wide nodes by the
// SAH-optimal dynamic programme of Ylitie, Karras and Laine (2017), children assigned to slots
// by ray octant, child boxes quantised conservatively (never smaller than the exact box).
#pragma once

#include <vector>

#include "src/geometry/bvh.h"
#include "src/geometry/traverse_wide.h"

namespace pt {

struct WideBvhResult {
  std::vector<WideBvhNode> nodes;   // root at 0; empty for an empty scene
  std::vector<uint32_t> primOrder;  // input index of each primitive slot (leaves' order)
  // Deepest wide node (root = 0). Traversal keeps one stack entry per level: the collapse is
  // never deeper than the binary tree, at most kBvhMaxDepth plus the levels that split leaves
  // of more than 3 primitives (under 32), which kWideStackSize covers.
  int maxDepth = 0;
  double sahCost = 0.0;             // node cost 1, primitive cost 0.3 (the collapse's model)
};

// Collapses `binary` (as BuildBvh returns it; primBounds are the input primitives' bounds, to
// split bigger leaves) into nodes whose leaves hold at most maxLeafPrims primitives (1 to 3),
// on `threads` threads (0: all cores, as BvhBuildOptions). Deterministic: the same nodes
// whatever the thread count.
WideBvhResult CollapseToWide(const BvhBuildResult& binary, const std::vector<Aabb>& primBounds,
                             int threads = 1, int maxLeafPrims = 3);

}  // namespace pt
