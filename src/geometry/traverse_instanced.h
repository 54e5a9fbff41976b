// Two-level traversal for scenes with instances: the top level is a BVH over the instances'
// world bounds; at its leaves the ray moves into each instance's object space and walks that
// mesh's own BVH (the bottom level). Both levels use the scene's layout (--bvh), in one loop
// per layout over one stack (InstanceLevel), with the node steps of traverse_wide.h (WideWalk)
// and the binary walk's rules of traverse_binary.h.
//
// The closest hit does not depend on the order of visits: of hits at exactly the same
// distance, the smaller (instance, PrimRef::tagIndex) wins, as tagIndex alone does in a flat
// scene. An identity instance (the world-space primitives, or a mesh placed as it is) sees the
// world ray unchanged, so its hits are bit for bit those of the flat scene.
#pragma once

#include "src/geometry/instance.h"
#include "src/geometry/shapes.h"
#include "src/geometry/traverse_binary.h"
#include "src/geometry/traverse_wide.h"

namespace pt {

// The nearest hit over all instances so far (or the first, for any-hit queries).
struct InstancedBest {
  uint32_t prim = HitRecord::kNoHit;
  uint32_t instance = kNoInstance;
  uint32_t tag = 0;  // prims[prim].tagIndex
  vec2 uv = vec2(0.0f);
  uint32_t tested = 0;

  PT_HDI bool Found() const { return prim != HitRecord::kNoHit; }
  // Whether (instance, tag) wins a tie against the best hit.
  PT_HDI bool Precedes(uint32_t inst, uint32_t t) const {
    return inst < instance || (inst == instance && t < tag);
  }
};

// The level a two-level walk is on: the top one (the world ray) or, after Enter, an instance's
// tree, walked with the object-space ray and distances less dt. Both layouts' walks keep one
// of these and their one stack: the instance's entries go above the top level's, and the walk
// returns to the top level when the stack is back at the mark Enter set. So the lanes of a GPU
// warp run the same node tests together whichever level each is on (a walk whose leaves ran
// another walk kept the top level's lanes waiting out the others' whole bottom walks, and held
// both levels' state at once).
struct InstanceLevel {
  const Ray& worldRay;
  float worldTMax;
  Ray ray;          // the current level's ray
  float tMax;       // the current level's limit (world tMax - dt in an instance)
  float dt = 0.0f;
  TriangleRayData triRay{};
  uint32_t instance = 0, primOffset = 0, nodeOffset = 0;
  int mark = -1;    // the stack size when the instance was entered; -1: the top level
  bool hit = false;  // a hit was taken in this instance

  PT_HDI InstanceLevel(const Ray& world, float worldLimit)
      : worldRay(world), worldTMax(worldLimit), ray(world), tMax(worldLimit) {}
  PT_HDI bool InInstance() const { return mark >= 0; }
  // Enters instance id with the stack at stackSize; false (staying on the top level) when its
  // object-space ray is not traceable.
  PT_HDI bool Enter(const SceneView& s, uint32_t id, int stackSize) {
    const Instance& inst = s.instances[id];
    float shift = 0.0f;
    const Ray r = (inst.flags & kInstanceIdentity) ? worldRay : ObjectRay(inst, worldRay, &shift);
    if (!TraceableRay(r)) return false;
    ray = r;
    dt = shift;
    triRay = TriangleRayData::Make(r.d);
    tMax = worldTMax - dt;
    instance = id;
    primOffset = inst.primOffset;
    nodeOffset = inst.nodeOffset;
    mark = stackSize;
    hit = false;
    return true;
  }
  // Back to the top level, the instance's hit (if any) limiting the world ray.
  PT_HDI void Leave() {
    if (hit) worldTMax = fminf(tMax + dt, worldTMax);
    ray = worldRay;
    tMax = worldTMax;
    mark = -1;
  }
  // The instance's primitive i of its mesh (primOffset + i in prims) against the object-space
  // ray: kClosest keeps the nearest (ties by (instance, tag)), kAny takes any. True when taken.
  // kHitTest as in IntersectPrim (false: no material of the scene asks for one).
  template <TraceMode kMode, bool kHitTest>
  PT_HDI bool TestPrim(const SceneView& s, uint32_t i, InstancedBest& best) {
    const uint32_t p = primOffset + i;
    ++best.tested;
    float t;
    vec2 uv;
    if (kMode == TraceMode::kAny) {
      if (!IntersectPrim<kHitTest>(s, p, ray, triRay, tMax, &t, &uv)) return false;
      best.prim = p;
      best.instance = instance;
      hit = true;
      return true;
    }
    // Once there is a hit, also admit one at exactly its distance: the smaller key wins.
    const float limit = best.Found() ? NextFloatUp(tMax) : tMax;
    if (!IntersectPrim<kHitTest>(s, p, ray, triRay, limit, &t, &uv)) return false;
    const uint32_t tag = s.prims[p].tagIndex;
    if (!(t < tMax) && !best.Precedes(instance, tag)) return false;
    tMax = t;
    best = InstancedBest{p, instance, tag, uv, best.tested};
    hit = true;
    return true;
  }
};

// Both levels of the wide layout in one loop (see InstanceLevel): a top-level primitive enters
// its instance, while the node's other instances and its interior children wait on the stack.
// Hits, culling and their order are those of a walk whose leaves walk their instances.
constexpr int kTwoLevelStackCapacity = 2 * kWideStackCapacity + 2;

template <TraceMode kMode, bool kHitTest>
PT_HDI void TraverseInstancedWide(const SceneView& s, const Ray& worldRay, float* tMaxInOut,
                                  InstancedBest& best, TraversalCounters* counters) {
  const detail::WideRay worldR = detail::MakeWideRay(worldRay);
  InstanceLevel level(worldRay, *tMaxInOut);
  const WideBvhNode* nodes = s.tlasWideNodes;
  detail::WideRay r = worldR;
  uint32_t nodesVisited = 0;
  detail::WideStack<kTwoLevelStackCapacity> stack;
  detail::WideWalk<kTwoLevelStackCapacity> w(stack);
  for (;;) {
    if (w.primMask == 0 && w.HasNode()) {
      ++nodesVisited;
      w.template VisitNext<true, kWideNearestFirst<kMode>>(nodes, r, level.tMax);
    }
    if (!level.InInstance() && w.primMask != 0) {  // enter the group's next instance
      const uint32_t bit = detail::LowestBit(w.primMask);
      const uint32_t rest = w.primMask & (w.primMask - 1u);
      if (w.HasNode()) w.Push(w.groupBase, w.groupMask);
      if (rest != 0) {
        w.Push(w.primBase, rest);
        ++w.postponed;
      }
      w.primMask = 0;
      w.groupMask = 0;
      w.first = 0;
      if (level.Enter(s, s.instanceOrder[w.primBase + bit], w.stackSize)) {
        r = detail::MakeWideRay(level.ray);
        nodes = s.wideNodes + level.nodeOffset;
        w.Restart();
      }
    }
    const bool done = w.TestPrims([&](uint32_t prim) {  // in an instance: its primitives
      return level.TestPrim<kMode, kHitTest>(s, prim, best) && kMode == TraceMode::kAny;
    });
    if (done) break;
    if (w.HasNode()) continue;
    if (level.InInstance() && w.stackSize == level.mark) {  // back to the top level
      level.Leave();
      nodes = s.tlasWideNodes;
      r = worldR;
    }
    if (!w.Pop()) break;
  }
  *tMaxInOut = level.worldTMax;
  if (counters) counters->nodes += nodesVisited;
}

// Both levels of the binary layout in one loop (see InstanceLevel). A top-level leaf enters its
// first instance; the leaf's others wait as one stack entry (kEnterBit | slot, the count of
// instances left in place of a distance), taken whatever the distance, as a walk whose leaves
// walk their instances tests every instance of a leaf.
constexpr int kTwoLevelBinaryStackSize = 2 * kBvhStackSize + 1;

template <TraceMode kMode, bool kHitTest>
PT_HDI void TraverseInstancedBinary(const SceneView& s, const Ray& worldRay, float* tMaxInOut,
                                    InstancedBest& best, TraversalCounters* counters) {
  constexpr uint32_t kEnterBit = 0x80000000u;
  const vec3 worldInvDir(1.0f / worldRay.d.x, 1.0f / worldRay.d.y, 1.0f / worldRay.d.z);
  InstanceLevel level(worldRay, *tMaxInOut);
  const BvhNode* nodes = s.tlasNodes;
  vec3 invDir = worldInvDir;
  uint32_t nodesVisited = 0, stackNode[kTwoLevelBinaryStackSize];
  float stackT[kTwoLevelBinaryStackSize];
  int stackSize = 0;
  auto push = [&](uint32_t entry, float t) {
    if (stackSize == kTwoLevelBinaryStackSize) return;  // never: one entry a level, as Traverse
    stackNode[stackSize] = entry;
    stackT[stackSize] = t;
    ++stackSize;
  };
  uint32_t node = 0, leafLeft = 0;  // leafLeft: instances of the leaf from slot node & ~kEnterBit
  float tEntry;
  bool active = IntersectAabb(nodes[0].boundsMin, nodes[0].boundsMax, worldRay.o, invDir,
                              level.tMax, &tEntry);
  while (active) {
    if (node & kEnterBit) {  // the top level's instance in slot `node & ~kEnterBit`
      const uint32_t slot = node & ~kEnterBit;
      if (leafLeft > 1) push(kEnterBit | (slot + 1), float(leafLeft - 1));
      if (level.Enter(s, s.instanceOrder[slot], stackSize)) {
        nodes = s.nodes + level.nodeOffset;
        invDir = level.triRay.invDir;  // 1 / d of the object-space ray
        node = 0;
        if (IntersectAabb(nodes[0].boundsMin, nodes[0].boundsMax, level.ray.o, invDir,
                          level.tMax, &tEntry))
          continue;
      }
    } else {
      ++nodesVisited;
      const BvhNode& n = nodes[node];
      if (n.IsLeaf() && !level.InInstance()) {
        node = kEnterBit | n.leftOrFirst;
        leafLeft = n.count;
        continue;
      }
      if (n.IsLeaf()) {
        bool done = false;
        for (uint32_t i = n.leftOrFirst; i < n.leftOrFirst + n.count && !done; ++i)
          done = level.TestPrim<kMode, kHitTest>(s, i, best) && kMode == TraceMode::kAny;
        if (done) break;
      } else if (n.count == 0 && n.leftOrFirst != 0 &&  // interior, as Traverse(BinaryBvh)
                 detail::StepIntoChildren(nodes, n.leftOrFirst, level.ray.o, invDir, level.tMax,
                                          &node, push)) {
        continue;
      }
    }
    // The nearest waiting entry that may still hold something closer than tMax.
    active = false;
    while (!active) {
      if (level.InInstance() && stackSize == level.mark) {  // back to the top level
        level.Leave();
        nodes = s.tlasNodes;
        invDir = worldInvDir;
      }
      if (stackSize == 0) break;
      --stackSize;
      node = stackNode[stackSize];
      if (node & kEnterBit) leafLeft = uint32_t(stackT[stackSize]);
      active = (node & kEnterBit) || stackT[stackSize] <= level.tMax * kAabbFarScale;
    }
  }
  *tMaxInOut = level.worldTMax;
  if (counters) counters->nodes += nodesVisited;
}

// Every instance's primitives against the world ray, into best, in layout L.
template <BvhLayout L, TraceMode kMode, bool kHitTest>
PT_HDI void TraverseInstances(const SceneView& s, const Ray& ray, float* tMax, InstancedBest& best,
                              TraversalCounters* counters) {
  if (s.instanceCount == 0 || !TraceableRay(ray)) return;
  if constexpr (L == BvhLayout::kWide)
    TraverseInstancedWide<kMode, kHitTest>(s, ray, tMax, best, counters);
  else
    TraverseInstancedBinary<kMode, kHitTest>(s, ray, tMax, best, counters);
}

// Nearest hit over every instance with 0 < t < tMax (as IntersectClosest in a flat scene),
// hit->instance naming the placement. kHitTest: whether some material asks for a hit test.
template <BvhLayout L, bool kHitTest = true>
PT_HDI bool IntersectClosestInstanced(const SceneView& s, const Ray& ray, float tMax,
                                      HitRecord* hit, TraversalCounters* counters) {
  InstancedBest best;
  float t = tMax;
  TraverseInstances<L, TraceMode::kClosest, kHitTest>(s, ray, &t, best, counters);
  if (counters) counters->prims += best.tested;
  hit->t = t;
  hit->prim = best.prim;
  hit->uv = best.uv;
  hit->instance = best.instance;
  return best.Found();
}

template <BvhLayout L, bool kHitTest = true>
PT_HDI bool IntersectAnyInstanced(const SceneView& s, const Ray& ray, float tMax,
                                  TraversalCounters* counters) {
  InstancedBest best;
  float t = tMax;
  TraverseInstances<L, TraceMode::kAny, kHitTest>(s, ray, &t, best, counters);
  if (counters) counters->prims += best.tested;
  return best.Found();
}

}  // namespace pt
