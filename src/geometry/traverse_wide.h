// Wide (8-ary, compressed) BVH traversal after Ylitie, Karras and Laine (2017): a node is read
// with five 16-byte loads, its eight quantised child boxes are tested at once, and the hit
// children are kept as a bit mask (a "group") instead of one stack entry each. Interior hits
// are visited in the order the build chose for the ray's octant; the primitives of hit leaves
// go to the leaf callback (same contract as traverse_binary.h) one at a time.
//
// The box test is conservative although it works on quantised boxes with the cheap form
// t = q * (scale / d) + (origin - o) / d: see WideSlabs below.
#pragma once

#include "src/geometry/traverse_binary.h"

#if !PT_IS_GPU_CODE && defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pt {

// One stack entry per level of the wide tree (bvh_wide.h checks the tree fits).
constexpr int kWideStackSize = kBvhMaxDepth + 32;

struct WideBvh {
  const WideBvhNode* nodes = nullptr;
  uint32_t nodeCount = 0;
};

PT_HDI WideBvh SceneWideBvh(const SceneView& s) { return WideBvh{s.wideNodes, s.nodeCount}; }

namespace detail {

PT_HDI uint32_t HighestBit(uint32_t x) {  // x != 0
#if PT_IS_GPU_CODE
  return 31u - uint32_t(__clz(x));
#else
  return 31u - uint32_t(__builtin_clz(x));
#endif
}
PT_HDI uint32_t LowestBit(uint32_t x) {  // x != 0
#if PT_IS_GPU_CODE
  return uint32_t(__ffs(x)) - 1u;
#else
  return uint32_t(__builtin_ctz(x));
#endif
}
PT_HDI uint32_t PopCount8(uint32_t x) {  // x < 256
#if PT_IS_GPU_CODE
  return uint32_t(__popc(x));
#else
  // Baseline x86-64 has no popcnt instruction (the builtin becomes a libgcc call).
  x = x - ((x >> 1) & 0x55u);
  x = (x & 0x33u) + ((x >> 2) & 0x33u);
  return (x + (x >> 4)) & 0x0fu;
#endif
}

// Byte k of w as a float, exactly. On the GPU a byte permute into 2^23 + b and one subtraction
// replace the quarter-rate integer-to-float conversion.
PT_HDI float ByteAsFloat(uint32_t w, uint32_t k) {
#if PT_IS_GPU_CODE
  return __uint_as_float(__byte_perm(w, 0x4B000000u, 0x7540u | k)) - 8388608.0f;
#else
  return float((w >> (8u * k)) & 0xffu);
#endif
}

// q * a + b: fused on the GPU, two roundings on the host; WideSlabs' bound covers both.
PT_HDI float MulAdd(float q, float a, float b) {
#if PT_IS_GPU_CODE
  return __fmaf_rn(q, a, b);
#else
  return q * a + b;
#endif
}

PT_HDI float FloatFromBits(uint32_t bits) {
#if PT_IS_GPU_CODE
  return __uint_as_float(bits);
#else
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
#endif
}

// The node as 20 words, read as five 16-byte loads on the GPU.
struct WideNodeWords {
  uint32_t w[20];
};

PT_HDI_HOT WideNodeWords LoadWideNode(const WideBvhNode* node) {
  WideNodeWords n;
#if PT_IS_GPU_CODE
  const uint4* p = reinterpret_cast<const uint4*>(node);
  for (int i = 0; i < 5; ++i) {
    uint4 v = __ldg(p + i);
    n.w[4 * i] = v.x;
    n.w[4 * i + 1] = v.y;
    n.w[4 * i + 2] = v.z;
    n.w[4 * i + 3] = v.w;
  }
#else
  static_assert(sizeof(WideBvhNode) == sizeof(WideNodeWords), "WideBvhNode is 80 bytes");
  std::memcpy(&n, node, sizeof n);
#endif
  return n;
}

// Per-ray constants of the wide box test.
struct WideRay {
  vec3 o, invDir;
  uint32_t octInv;  // 7 - octant (octant bit a: the ray goes towards -a)
  bool neg[3];
  // Host: the words of WideNodeWords holding each axis's near and far planes (qlo at 8 + 2a,
  // qhi at 14 + 2a; swapped where the ray goes down), read by index rather than by selects.
  uint32_t nearWord[3], farWord[3];
};

// Error bound of the slab distances (for a box bound b = origin + q * scale, exact value
// T = (b - o) / d), computed as t = q * adj + (A -+ E) with A = (origin - o) * invDir,
// adj = scale * invDir (exact: scale is a power of two) and E = gamma(7) |A|. Each of the
// roundings of 1/d, origin - o, the product, q * adj (host only) and the sum gives
// t = (1 + theta) T + zeta with |theta| <= gamma(3) and |zeta| <= gamma(6) |A|: so moving the
// near distances down and the far ones up by E leaves only relative error, which the far scale
// below absorbs, as in IntersectAabb (Ize 2013). A NaN (a zero direction component, 0 * inf)
// is ignored by the min/max and so never culls.
constexpr float kWideSlack = Gamma(7);
constexpr float kWideFarScale = 1.0f + 2.0f * Gamma(4);

// A hit child's mask bits: meta >> 5 at bit meta & 31, where an interior child's bit (24 +
// slot: bits 3 and 4 set) has its slot mirrored by the ray's octant (^ octInv). Decoded for a
// node half's four meta bytes at once, with a few word-wide operations instead of several per
// slot (tests/bvh_wide_test.cpp checks it against the per-byte rule).
struct SlotBits4 {
  uint32_t bitIndex4, childBits4;

  PT_HDI static SlotBits4 Decode(uint32_t meta4, uint32_t octInv) {
    const uint32_t interior4 = meta4 & (meta4 << 1) & 0x10101010u;
    return SlotBits4{(meta4 ^ ((interior4 >> 4) * octInv)) & 0x1f1f1f1fu,
                     (meta4 >> 5) & 0x07070707u};
  }
  PT_HDI uint32_t HitBits(uint32_t k) const {
    return ((childBits4 >> (8u * k)) & 0xffu) << ((bitIndex4 >> (8u * k)) & 0xffu);
  }
};

#if !PT_IS_GPU_CODE && defined(__SSE2__)
#define PT_WIDE_SSE 1
// The host's version of the test below: four slots per SSE instruction, the same operations
// in the same order (so the same mask). _mm_max_ps(b, a) is b > a ? b : a, which ignores a NaN
// in b exactly as MaxIgnoreNan(a, b) does.
inline __m128 WideBytes(uint32_t w) {
  const __m128i zero = _mm_setzero_si128();
  __m128i v = _mm_cvtsi32_si128(int(w));
  v = _mm_unpacklo_epi16(_mm_unpacklo_epi8(v, zero), zero);
  return _mm_cvtepi32_ps(v);
}

// always_inline spelled out: host-only code, so not PT_HDI_HOT (made for host-and-device code).
inline __attribute__((always_inline)) uint32_t IntersectWideChildrenSse(
    const WideNodeWords& n, const WideRay& r, float tMax, const float adj[3], const float nearD[3],
    const float farD[3]) {
  const __m128 tMaxV = _mm_set1_ps(tMax), scale = _mm_set1_ps(kWideFarScale);
  uint32_t hits = 0;
  for (int half = 0; half < 2; ++half) {
    __m128 t0 = _mm_setzero_ps(), t1 = tMaxV;
    for (int a = 0; a < 3; ++a) {
      const __m128 adjA = _mm_set1_ps(adj[a]);
      __m128 tn = _mm_add_ps(_mm_mul_ps(WideBytes(n.w[r.nearWord[a] + half]), adjA),
                             _mm_set1_ps(nearD[a]));
      __m128 tf = _mm_add_ps(_mm_mul_ps(WideBytes(n.w[r.farWord[a] + half]), adjA),
                             _mm_set1_ps(farD[a]));
      t0 = _mm_max_ps(tn, t0);
      t1 = _mm_min_ps(tf, t1);
    }
    const uint32_t mask = uint32_t(_mm_movemask_ps(_mm_cmple_ps(t0, _mm_mul_ps(t1, scale))));
    // Without branches: which slots a random ray hits is unpredictable.
    const SlotBits4 slots = SlotBits4::Decode(n.w[6 + half], r.octInv);
    for (uint32_t k = 0; k < 4; ++k) hits |= slots.HitBits(k) & (0u - ((mask >> k) & 1u));
  }
  return hits;
}
#endif

// Bit mask of the children of `n` that the ray enters within [0, tMax]: interior children at
// bit 24 + (slot ^ octInv), each leaf's primitives at bits [offset, offset + count).
PT_HDI_HOT uint32_t IntersectWideChildren(const WideNodeWords& n, const WideRay& r, float tMax) {
  const float px = FloatFromBits(n.w[0]), py = FloatFromBits(n.w[1]), pz = FloatFromBits(n.w[2]);
  const uint32_t e = n.w[3];
  const float adjX = FloatFromBits((e & 0xffu) << 23) * r.invDir.x;
  const float adjY = FloatFromBits(((e >> 8) & 0xffu) << 23) * r.invDir.y;
  const float adjZ = FloatFromBits(((e >> 16) & 0xffu) << 23) * r.invDir.z;
  const float ax = (px - r.o.x) * r.invDir.x, ay = (py - r.o.y) * r.invDir.y,
              az = (pz - r.o.z) * r.invDir.z;
  const float ex = kWideSlack * fabsf(ax), ey = kWideSlack * fabsf(ay), ez = kWideSlack * fabsf(az);
  const float nearX = ax - ex, nearY = ay - ey, nearZ = az - ez;
  const float farX = ax + ex, farY = ay + ey, farZ = az + ez;
#ifdef PT_WIDE_SSE
  const float adj[3] = {adjX, adjY, adjZ}, nearD[3] = {nearX, nearY, nearZ},
              farD[3] = {farX, farY, farZ};
  return IntersectWideChildrenSse(n, r, tMax, adj, nearD, farD);
#else
  uint32_t hits = 0;
  for (int half = 0; half < 2; ++half) {
    // qlo words at 8 + 2 axis + half, qhi at 14 + 2 axis + half; swapped where the ray goes down.
    uint32_t loX = n.w[8 + half], hiX = n.w[14 + half];
    uint32_t loY = n.w[10 + half], hiY = n.w[16 + half];
    uint32_t loZ = n.w[12 + half], hiZ = n.w[18 + half];
    const uint32_t qnX = r.neg[0] ? hiX : loX, qfX = r.neg[0] ? loX : hiX;
    const uint32_t qnY = r.neg[1] ? hiY : loY, qfY = r.neg[1] ? loY : hiY;
    const uint32_t qnZ = r.neg[2] ? hiZ : loZ, qfZ = r.neg[2] ? loZ : hiZ;
    const SlotBits4 slots = SlotBits4::Decode(n.w[6 + half], r.octInv);
    for (uint32_t k = 0; k < 4; ++k) {
      float t0 = MulAdd(ByteAsFloat(qnX, k), adjX, nearX);
      t0 = detail::MaxIgnoreNan(t0 > 0.0f ? t0 : 0.0f, MulAdd(ByteAsFloat(qnY, k), adjY, nearY));
      t0 = detail::MaxIgnoreNan(t0, MulAdd(ByteAsFloat(qnZ, k), adjZ, nearZ));
      float t1 = detail::MinIgnoreNan(tMax, MulAdd(ByteAsFloat(qfX, k), adjX, farX));
      t1 = detail::MinIgnoreNan(t1, MulAdd(ByteAsFloat(qfY, k), adjY, farY));
      t1 = detail::MinIgnoreNan(t1, MulAdd(ByteAsFloat(qfZ, k), adjZ, farZ));
      if (t0 <= t1 * kWideFarScale) hits |= slots.HitBits(k);
    }
  }
  return hits;
#endif
}

}  // namespace detail

// On the GPU, a node's hit primitives are tested at once only when enough lanes of the warp have
// some (Ylitie et al. 2017's postponing): otherwise they wait on the stack as a primitive group
// while the warp keeps traversing together. At most kWidePostponed such groups at a time, on
// top of the one entry per level of the tree.
constexpr int kWidePostponed = 16;
constexpr int kWideStackCapacity = kWideStackSize + kWidePostponed;

namespace detail {

// Whether this lane's primitives should wait: fewer than a fifth of the active lanes have any.
PT_HDI bool PostponePrims(bool hasPrims) {
#if PT_IS_GPU_CODE
  const uint32_t active = __activemask();
  const uint32_t withPrims = __ballot_sync(active, hasPrims);
  return hasPrims && 5 * __popc(withPrims) < __popc(active);
#else
  return false;  // one ray at a time: nothing to wait for
#endif
}

}  // namespace detail

// Walks a wide BVH: the current node group (interior hits of a node, plus its child base and
// interior mask) is consumed highest bit first; the rest of a group waits on the stack. Hit
// primitives go to the leaf callback; *tMax as in the binary traversal. A stack entry whose mask
// has no bit above 23 is a postponed primitive group (base, primitive bits).
template <TraceMode kMode, typename LeafFn>
PT_HDI void Traverse(const WideBvh& bvh, const Ray& ray, float* tMaxInOut, LeafFn& leaf,
                     TraversalCounters* counters) {
  if (bvh.nodeCount == 0 || !TraceableRay(ray)) return;
  float tMax = *tMaxInOut;
  detail::WideRay r;
  r.o = ray.o;
  r.invDir = vec3(1.0f / ray.d.x, 1.0f / ray.d.y, 1.0f / ray.d.z);
  r.neg[0] = r.invDir.x < 0.0f;  // 1/d is never -0; 1/-0 = -inf counts as negative
  r.neg[1] = r.invDir.y < 0.0f;
  r.neg[2] = r.invDir.z < 0.0f;
  r.octInv = 7u - (uint32_t(r.neg[0]) | uint32_t(r.neg[1]) << 1 | uint32_t(r.neg[2]) << 2);
  for (int a = 0; a < 3; ++a) {
    r.nearWord[a] = (r.neg[a] ? 14u : 8u) + 2u * uint32_t(a);
    r.farWord[a] = (r.neg[a] ? 8u : 14u) + 2u * uint32_t(a);
  }
  uint32_t nodesVisited = 0;

  uint32_t stackBase[kWideStackCapacity], stackMask[kWideStackCapacity];
  int stackSize = 0, postponed = 0;
  auto push = [&](uint32_t base, uint32_t mask) {
    stackBase[stackSize] = base;
    stackMask[stackSize] = mask;
    ++stackSize;
  };
  // A group: base = first interior child, mask = interior hit bits 24-31 | interior mask 0-7.
  // The root is the one child of a virtual group (base 0, empty interior mask: index 0).
  uint32_t groupBase = 0, groupMask = 0x80000000u;
  uint32_t primBase = 0, primMask = 0;
  for (;;) {
    if (primMask == 0 && groupMask > 0x00ffffffu) {
      const uint32_t bit = detail::HighestBit(groupMask);
      groupMask &= ~(1u << bit);
      if (groupMask > 0x00ffffffu && stackSize < kWideStackCapacity) push(groupBase, groupMask);
      const uint32_t slot = (bit - 24u) ^ r.octInv;
      const uint32_t index =
          groupBase + detail::PopCount8(groupMask & 0xffu & ((1u << slot) - 1u));
      ++nodesVisited;
      const detail::WideNodeWords n = detail::LoadWideNode(bvh.nodes + index);
      const uint32_t hits = detail::IntersectWideChildren(n, r, tMax);
      groupBase = n.w[4];
      groupMask = (hits & 0xff000000u) | (n.w[3] >> 24);
      primBase = n.w[5];
      primMask = hits & 0x00ffffffu;
      if (detail::PostponePrims(primMask != 0) && groupMask > 0x00ffffffu &&
          postponed < kWidePostponed && stackSize < kWideStackCapacity) {
        push(primBase, primMask);
        ++postponed;
        primMask = 0;
      }
    }
    while (primMask != 0) {
      const uint32_t bit = detail::LowestBit(primMask);
      primMask &= primMask - 1u;
      if (leaf(primBase + bit, 1u, &tMax) && kMode == TraceMode::kAny) {
        groupMask = 0;  // done: the stack is dropped below
        primMask = 0;
        stackSize = 0;
        break;
      }
    }
    if (groupMask <= 0x00ffffffu) {
      if (stackSize == 0) break;
      --stackSize;
      if (stackMask[stackSize] > 0x00ffffffu) {
        groupBase = stackBase[stackSize];
        groupMask = stackMask[stackSize];
      } else {  // a postponed primitive group
        primBase = stackBase[stackSize];
        primMask = stackMask[stackSize];
        groupMask = 0;
        --postponed;
      }
    }
  }
  *tMaxInOut = tMax;
  if (counters) counters->nodes += nodesVisited;
}

}  // namespace pt
