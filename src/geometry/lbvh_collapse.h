// The linear BVH (lbvh.h) collapsed into the wide layout on the device that built it: the
// collapse of bvh_wide.cpp (Ylitie, Karras and Laine 2017's SAH-optimal dynamic programme over
// how a node's 8 slots are spread over its binary descendants, leaves of at most 3 primitives),
// as stage bodies. The costs are found from the leaves up as the boxes were (the second child
// to arrive computes its parent's), and the wide nodes are emitted a level at a time: each of a
// level's nodes gathers its slots from the programme's choices (CountLevel), a scan gives each
// its children's and primitives' places, and EmitNode writes it. The same tree as the host's
// collapse, stored breadth first instead of depth first.
#pragma once

#include "src/geometry/lbvh.h"

namespace pt {
namespace lbvh {

constexpr int kCollapseWidth = 8;
constexpr uint32_t kCollapseLeafPrims = 3;
constexpr float kCollapseNodeCost = 1.0f;  // the host collapse's cost model
constexpr float kCollapsePrimCost = 0.3f;

struct CollapseArrays {
  float* cost = nullptr;       // [8 (2n - 1)]: [node * 8 + slots - 1]
  int8_t* choice = nullptr;    // same shape: 0 one slot, -1 as with one fewer, k: k go left
  int8_t* split8 = nullptr;    // [2n - 1] the best split of 8 slots over the children
  uint8_t* asLeaf = nullptr;   // [2n - 1] one slot: a leaf (1) or a node (0)
  uint32_t* visits = nullptr;  // [n - 1] zeroed
  // A level's tasks (binary node, its wide node's index) and what CountLevel found.
  const uint32_t* taskNode = nullptr;
  const uint32_t* taskWide = nullptr;
  uint32_t* taskChildren = nullptr;  // [8 t + k]; count in taskCount
  uint32_t* taskCount = nullptr;
  uint32_t* taskInterior = nullptr;  // interior slots of task t (its wide children)
  uint32_t* taskPrims = nullptr;     // primitives of its leaf slots
  const uint32_t* interiorOffset = nullptr;  // exclusive scans of the two
  const uint32_t* primOffset = nullptr;
  uint32_t nodeBase = 0, primBase = 0;  // where this level's children and primitives start
  uint32_t* nextNode = nullptr;         // the next level's tasks
  uint32_t* nextWide = nullptr;
  WideBvhNode* wide = nullptr;
  uint32_t* primOrder = nullptr;        // input index of each wide primitive slot
  float* sah = nullptr;                 // [wide node] its part of the SAH cost (unnormalised)
};

PT_HDI float BoxArea(const Aabb& b) {
  if (b.IsEmpty()) return 0.0f;
  const vec3 d = b.hi - b.lo;
  return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

PT_HDI bool IsLeafNode(const Arrays& a, uint32_t node) { return node >= a.n - 1; }
PT_HDI uint32_t FirstPrim(const Arrays& a, uint32_t node) {  // in sorted order
  return IsLeafNode(a, node) ? node - (a.n - 1) : a.rangeLo[node];
}
PT_HDI uint32_t PrimCount(const Arrays& a, uint32_t node) {
  return IsLeafNode(a, node) ? 1u : a.rangeHi[node] - a.rangeLo[node] + 1u;
}

// ---- The programme's costs, from the leaves up ----

PT_HDI void NodeCost(const Arrays& a, const CollapseArrays& c, uint32_t i) {
  const float area = BoxArea(GetBox(a, i));
  float* cost = c.cost + size_t(i) * kCollapseWidth;
  int8_t* choice = c.choice + size_t(i) * kCollapseWidth;
  if (IsLeafNode(a, i)) {
    for (int s = 1; s <= kCollapseWidth; ++s) {
      cost[s - 1] = area * kCollapsePrimCost;
      choice[s - 1] = int8_t(s == 1 ? 0 : -1);
    }
    c.asLeaf[i] = 1;
    c.split8[i] = 0;
    return;
  }
  const float* costL = c.cost + size_t(a.left[i]) * kCollapseWidth;
  const float* costR = c.cost + size_t(a.right[i]) * kCollapseWidth;
  float dist[kCollapseWidth + 1];
  int8_t arg[kCollapseWidth + 1];
  for (int j = 2; j <= kCollapseWidth; ++j) {
    dist[j] = kInfinity;
    arg[j] = 1;
    for (int k = 1; k < j; ++k) {
      const float v = LoadShared(costL + k - 1) + LoadShared(costR + j - k - 1);
      if (v < dist[j]) dist[j] = v, arg[j] = int8_t(k);
    }
  }
  const uint32_t prims = PrimCount(a, i);
  const float leaf = prims <= kCollapseLeafPrims ? area * kCollapsePrimCost * float(prims)
                                                 : kInfinity;
  const float internal = dist[kCollapseWidth] + area * kCollapseNodeCost;
  c.split8[i] = arg[kCollapseWidth];
  c.asLeaf[i] = leaf <= internal ? 1 : 0;
  cost[0] = leaf < internal ? leaf : internal;
  choice[0] = 0;
  for (int s = 2; s <= kCollapseWidth; ++s) {
    const bool distribute = dist[s] < cost[s - 2];
    cost[s - 1] = distribute ? dist[s] : cost[s - 2];
    choice[s - 1] = distribute ? arg[s] : int8_t(-1);
  }
}

PT_HDI void CollapseCosts(const Arrays& a, const CollapseArrays& c, uint32_t leaf) {
  uint32_t node = a.n - 1 + leaf;
  NodeCost(a, c, node);
  while (node != 0) {
    node = a.parent[node];
    if (AtomicAdd(&c.visits[node], 1u) == 0) return;
    NodeCost(a, c, node);
  }
}

// ---- Emission, a level at a time ----

// The binary nodes that become interior node b's slots (as bvh_wide.cpp's Gather with 8).
PT_HDI uint32_t Gather(const Arrays& a, const CollapseArrays& c, uint32_t b, uint32_t out[8]) {
  struct Item {
    uint32_t node;
    int slots;
  };
  Item stack[2 * kCollapseWidth + 2];
  int top = 0;
  stack[top++] = Item{a.right[b], kCollapseWidth - c.split8[b]};
  stack[top++] = Item{a.left[b], c.split8[b]};
  uint32_t count = 0;
  while (top > 0) {
    const Item it = stack[--top];
    int s = it.slots;
    const int8_t* choice = c.choice + size_t(it.node) * kCollapseWidth;
    while (s > 1 && choice[s - 1] == -1) --s;
    if (choice[s - 1] == 0) {
      if (count < uint32_t(kCollapseWidth)) out[count++] = it.node;
      continue;
    }
    const int left = choice[s - 1];
    stack[top++] = Item{a.right[it.node], s - left};
    stack[top++] = Item{a.left[it.node], left};
  }
  return count;
}

PT_HDI void CountLevel(const Arrays& a, const CollapseArrays& c, uint32_t t) {
  uint32_t* children = c.taskChildren + size_t(t) * kCollapseWidth;
  const uint32_t count = Gather(a, c, c.taskNode[t], children);
  uint32_t interior = 0, prims = 0;
  for (uint32_t k = 0; k < count; ++k) {
    if (c.asLeaf[children[k]]) prims += PrimCount(a, children[k]);
    else ++interior;
  }
  c.taskCount[t] = count;
  c.taskInterior[t] = interior;
  c.taskPrims[t] = prims;
}

// Children to slots as bvh_wide.cpp's AssignSlots: slot s takes, greedily, the child that
// rays of octant s meet first (the smallest centroid projection on the octant's diagonal).
PT_HDI void AssignSlots(const Aabb* boxes, uint32_t count, int slotOf[8]) {
  Aabb parent;
  for (uint32_t k = 0; k < count; ++k) parent.Extend(boxes[k]);
  const vec3 center = parent.Centroid();
  float cost[8][8];
  for (uint32_t k = 0; k < count; ++k) {
    const vec3 rel = boxes[k].Centroid() - center;
    for (int s = 0; s < 8; ++s) {
      const vec3 dir((s & 1) ? -1.0f : 1.0f, (s & 2) ? -1.0f : 1.0f, (s & 4) ? -1.0f : 1.0f);
      cost[k][s] = rel.x * dir.x + rel.y * dir.y + rel.z * dir.z;
    }
  }
  bool used[8] = {false, false, false, false, false, false, false, false};
  for (uint32_t k = 0; k < count; ++k) slotOf[k] = -1;
  for (uint32_t round = 0; round < count; ++round) {
    int bc = -1, bs = -1;
    for (uint32_t k = 0; k < count; ++k) {
      if (slotOf[k] >= 0) continue;
      for (int s = 0; s < 8; ++s) {
        if (!used[s] && (bc < 0 || cost[k][s] < cost[bc][bs])) bc = int(k), bs = s;
      }
    }
    slotOf[bc] = bs;
    used[bs] = true;
  }
}

// ---- Conservative quantisation (bvh_wide.cpp's, in double on either side) ----

PT_HDI float FiniteOr(float v) { return isfinite(v) ? v : (v > 0.0f ? 3.4028235e38f : -3.4028235e38f); }

// x - origin exactly, as d + err (Knuth's TwoSum in double).
PT_HDI void ExactDifference(float x, float origin, double* d, double* err) {
  const double a = x, b = -double(origin);
  const double s = a + b, bb = s - a;
  *d = s;
  *err = (a - (s - bb)) + (b - bb);
}
PT_HDI int QuantizeDown(float x, float origin, double scale) {
  double d, err;
  ExactDifference(x, origin, &d, &err);
  double q = floor(d / scale);
  if (err < 0.0 && q * scale == d) q -= 1.0;
  return q < 0.0 ? 0 : int(q < 255.0 ? q : 255.0);
}
PT_HDI int QuantizeUp(float x, float origin, double scale) {
  double d, err;
  ExactDifference(x, origin, &d, &err);
  double q = ceil(d / scale);
  if (err > 0.0 && q * scale == d) q += 1.0;
  return q < 0.0 ? 0 : int(q < 1024.0 ? q : 1024.0);
}

PT_HDI void Quantize(const Aabb boxes[8], const bool used[8], WideBvhNode* node) {
  Aabb all, fin[8];
  for (int i = 0; i < 8; ++i) {
    if (!used[i]) continue;
    fin[i].lo = vec3(FiniteOr(boxes[i].lo.x), FiniteOr(boxes[i].lo.y), FiniteOr(boxes[i].lo.z));
    fin[i].hi = vec3(FiniteOr(boxes[i].hi.x), FiniteOr(boxes[i].hi.y), FiniteOr(boxes[i].hi.z));
    all.Extend(fin[i]);
  }
  node->origin = all.lo;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = axis == 0 ? all.lo.x : (axis == 1 ? all.lo.y : all.lo.z);
    const float hi = axis == 0 ? all.hi.x : (axis == 1 ? all.hi.y : all.hi.z);
    const double extent = double(hi) - double(lo);
    int k = extent > 0.0 ? int(ceil(log2(extent / 255.0))) : -126;
    k = k < -126 ? -126 : (k > 127 ? 127 : k);
    for (;; ++k) {  // rounding of log2 may leave the top bound one step out of reach
      const double scale = ldexp(1.0, k);
      bool fits = true;
      for (int i = 0; i < 8 && fits; ++i) {
        const float h = axis == 0 ? fin[i].hi.x : (axis == 1 ? fin[i].hi.y : fin[i].hi.z);
        fits = !used[i] || QuantizeUp(h, lo, scale) <= 255;
      }
      if (fits || k == 127) break;
    }
    const double scale = ldexp(1.0, k);
    node->exponent[axis] = uint8_t(k + 127);
    for (int i = 0; i < 8; ++i) {
      const float l = axis == 0 ? fin[i].lo.x : (axis == 1 ? fin[i].lo.y : fin[i].lo.z);
      const float h = axis == 0 ? fin[i].hi.x : (axis == 1 ? fin[i].hi.y : fin[i].hi.z);
      const int up = used[i] ? QuantizeUp(h, lo, scale) : 0;
      node->qlo[axis][i] = used[i] ? uint8_t(QuantizeDown(l, lo, scale)) : 255;
      node->qhi[axis][i] = used[i] ? uint8_t(up < 255 ? up : 255) : 0;
    }
  }
}

// Task t's wide node: slots assigned, leaf primitives written, quantised; its interior
// children become the next level's tasks, in slot order from its childBase.
PT_HDI void EmitNode(const Arrays& a, const CollapseArrays& c, uint32_t t) {
  const uint32_t* children = c.taskChildren + size_t(t) * kCollapseWidth;
  const uint32_t count = c.taskCount[t];
  Aabb boxes[8];
  for (uint32_t k = 0; k < count; ++k) boxes[k] = GetBox(a, children[k]);
  int slotOf[8];
  AssignSlots(boxes, count, slotOf);
  int childAt[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  for (uint32_t k = 0; k < count; ++k) childAt[slotOf[k]] = int(k);
  WideBvhNode node{};
  node.childBase = c.nodeBase + c.interiorOffset[t];
  node.primBase = c.primBase + c.primOffset[t];
  Aabb slotBox[8], all;
  bool used[8];
  uint32_t interior = 0, prims = 0;
  float sah = 0.0f;
  for (int s = 0; s < 8; ++s) {
    used[s] = childAt[s] >= 0;
    if (!used[s]) continue;
    const uint32_t b = children[childAt[s]];
    slotBox[s] = boxes[childAt[s]];
    all.Extend(slotBox[s]);
    if (c.asLeaf[b]) {  // its primitives (at most 3, contiguous in sorted order)
      const uint32_t n = PrimCount(a, b), first = FirstPrim(a, b);
      for (uint32_t j = 0; j < n; ++j) c.primOrder[node.primBase + prims + j] = a.values[first + j];
      node.meta[s] = uint8_t((((1u << n) - 1u) << 5) | prims);
      prims += n;
      sah += BoxArea(slotBox[s]) * kCollapsePrimCost * float(n);
    } else {
      node.innerMask = uint8_t(node.innerMask | (1u << s));
      node.meta[s] = uint8_t((1u << 5) | (24u + uint32_t(s)));
      const uint32_t next = c.interiorOffset[t] + interior++;
      c.nextNode[next] = b;
      c.nextWide[next] = node.childBase + (next - c.interiorOffset[t]);
    }
  }
  sah += BoxArea(all) * kCollapseNodeCost;
  Quantize(slotBox, used, &node);
  c.wide[c.taskWide[t]] = node;
  c.sah[c.taskWide[t]] = sah;
}

}  // namespace lbvh
}  // namespace pt
