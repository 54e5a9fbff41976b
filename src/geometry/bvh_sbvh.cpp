// TEMPORARY (replaced before commit)
#include "src/geometry/bvh.h"
namespace pt {
BvhBuildResult BuildSbvh(const std::vector<Aabb>& primBounds, const BvhBuildOptions& options,
                         int maxDepth, const PrimClipper& clip) {
  BvhBuildOptions o = options; o.builder = BvhBuilder::kSah;
  return BuildBvh(primBounds, o, maxDepth);
}
}
