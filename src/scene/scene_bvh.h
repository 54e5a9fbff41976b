// The pieces of BuildScene that instancing builds its levels from (src/scene/build_scene.cpp).
#pragma once

#include <vector>

#include "src/geometry/aabb.h"
#include "src/scene/scene.h"

namespace pt {

// Whether hits on a material's primitives need its verdict (alpha, back-face culling;
// src/materials/alpha.h): such PrimRefs carry kHitTestBit.
bool NeedsHitTest(const Material& m);

// Every shape of the scene as an unordered PrimRef with its bounds, except the triangles
// flagged in skipTriangle (an instanced mesh's, which live in their own bottom level).
// threads: for a big mesh's triangles when none is skipped (0: every core); the result is the
// same for any count.
void CollectPrimitives(const SceneDesc& d, std::vector<PrimRef>& prims, std::vector<Aabb>& bounds,
                       const std::vector<bool>& skipTriangle = {}, int threads = 0);

// One BVH in the layout options ask for.
struct LayoutBvh {
  std::vector<BvhNode> nodes;          // binary layout
  std::vector<WideBvhNode> wideNodes;  // wide layout
  std::vector<uint32_t> order;         // input index of each leaf primitive slot
  double sahCost = 0.0;
  int depth = 0;
};

// The BVH over `bounds` (of the primitives `unordered`, whose shapes SBVH clips).
LayoutBvh BuildLayoutBvh(const SceneDesc& d, const std::vector<PrimRef>& unordered,
                         const std::vector<Aabb>& bounds, const BvhBuildOptions& options);

// scene.packedTriangles from scene.prims (BVH order), on `threads` (0: every core).
void PackTriangles(Scene& scene, int threads = 0);

}  // namespace pt
