// Builds the linear BVH of lbvh.h: on the host's threads (BuildLbvhHost), or through a device
// runner (the CUDA backend's, cuda/lbvh_cuda.cu) that runs the same stage bodies as kernels.
#pragma once

#include <vector>

#include "src/geometry/bvh.h"
#include "src/geometry/bvh_wide.h"
#include "src/geometry/lbvh.h"

namespace pt {

// The centroids' bounds as the Morton stage takes them: lower corner and cells per unit.
void LbvhGrid(const std::vector<Aabb>& bounds, vec3* sceneLo, vec3* cellsPerUnit);

// The tree in BuildBvh's layout with one primitive per leaf; threads as BvhBuildOptions (0: all
// cores). Deterministic: the same tree whatever the thread count, and the device's.
BvhBuildResult BuildLbvhHost(const std::vector<Aabb>& bounds, int threads = 0);

// The tree collapsed into the wide layout by lbvh_collapse.h's bodies on the host's threads:
// the same tree as CollapseToWide(BuildLbvhHost(...)) makes, stored breadth first. False for
// fewer than 2 primitives, or a tree deeper than the wide walks' stack.
bool CollapseLbvhHost(const std::vector<Aabb>& bounds, int threads, WideBvhResult* out);

// The CUDA backend's runners (cuda/lbvh_cuda.cu; only in builds with it): the stages as
// kernels on GPU `device`, the binary tree, or the wide one collapsed there too; false when
// they cannot run there.
bool BuildLbvhCuda(const std::vector<Aabb>& bounds, int device, BvhBuildResult* out);
bool BuildWideLbvhCuda(const std::vector<Aabb>& bounds, int device, WideBvhResult* out);

// The device runner's result already in `out` (nodes, primOrder, and each leaf's depth in
// depths): checks and finishes it (maxDepth). False when the tree is deeper than the walks'
// stacks allow (kBvhMaxDepth), which only pathological inputs reach.
bool FinishLbvh(const std::vector<uint32_t>& depths, BvhBuildResult* out);

}  // namespace pt
