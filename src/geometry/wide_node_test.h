// The wide BVH's node test (traverse_wide.h): which of a compressed node's eight quantised
// child boxes a ray enters, as the mask bits the traversal consumes. One rule, three bodies:
// scalar (GPU and hosts without SSE), four slots per SSE2 instruction, and all eight slots per
// AVX2 instruction on x86-64-v3 hosts (CMake's PT_HOST_ISA). All are conservative: a quantised
// box never culls what the exact box would keep (see kWideSlack), so whichever runs, the
// closest hit is the same (traverse.h).
#pragma once

#include <cstring>

#include "src/geometry/aabb.h"
#include "src/scene/scene_types.h"

#if !PT_IS_GPU_CODE && defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define PT_WIDE_AVX2 1
#elif !PT_IS_GPU_CODE && defined(__SSE2__)
#include <emmintrin.h>
#define PT_WIDE_SSE 1
#endif

namespace pt {
namespace detail {

// Byte k of w as a float, exactly. On the GPU a byte permute into 2^23 + b and one subtraction
// replace the quarter-rate integer-to-float conversion.
PT_HDI float ByteAsFloat(uint32_t w, uint32_t k) {
#if PT_IS_GPU_CODE
  return __uint_as_float(__byte_perm(w, 0x4B000000u, 0x7540u | k)) - 8388608.0f;
#else
  return float((w >> (8u * k)) & 0xffu);
#endif
}

// q * a + b: fused on the GPU, two roundings on the host; kWideSlack's bound covers both.
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
  // Bit a: the ray runs parallel to axis a's planes (d_a is zero, at most 2^-64 of the largest
  // component, or 1 / d_a overflows): its slab is also tested by where the origin lies
  // (ParallelSlotKeep), as its distances may be NaN.
  uint32_t parallel;
  bool neg[3];
  // Host: the words of WideNodeWords holding each axis's near and far planes (qlo at 8 + 2a,
  // qhi at 14 + 2a; swapped where the ray goes down), read by index rather than by selects.
  uint32_t nearWord[3], farWord[3];
#ifdef PT_WIDE_AVX2
  __m128 oV, invDirV;  // o and invDir as vectors (x, y, z, 0): one load each per node
#endif
};

// Error bound of the slab distances (for a box bound b = origin + q * scale, exact value
// T = (b - o) / d), computed as t = q * adj + (A -+ E) with A = (origin - o) * invDir,
// adj = scale * invDir (exact: scale is a power of two) and E = gamma(7) |A|. Each of the
// roundings of 1/d, origin - o, the product, q * adj (host only) and the sum gives
// t = (1 + theta) T + zeta with |theta| <= gamma(3) and |zeta| <= gamma(6) |A|: so moving the
// near distances down and the far ones up by E leaves only relative error, which the far scale
// below absorbs, as in IntersectAabb (Ize 2013). A NaN (a zero direction component, 0 * inf)
// is ignored by the min/max and so never culls: on such an axis (every parallel axis whose
// 1 / d is infinite, and any whose (origin - o) * invDir overflows) the distances say nothing,
// and the axis is culled by ParallelSlotKeep instead. (Without it a ray along an axis, as every
// shadow ray of an unrotated sun, culled by one axis only and walked most of the tree: 30-8000x
// slower than the binary walk, issue 28.)
constexpr float kWideSlack = Gamma(7);
// As kAabbFarScale (whose culling argument holds here too: theta is within gamma(3)), with one
// more rounding of headroom.
constexpr float kWideFarScale = 1.0f + 2.0f * Gamma(6);

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

// Component a of v by value (as shapes.h's Component, which this header does not include).
PT_HDI float WideAxis(vec3 v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }

// Which of the four bytes of w are at most v (0xff each), or at least v.
PT_HDI uint32_t BytesAtMost(uint32_t w, uint32_t v) {
#if PT_IS_GPU_CODE
  return __vcmpleu4(w, v * 0x01010101u);
#else
  uint32_t m = 0;
  for (uint32_t k = 0; k < 32; k += 8) m |= ((w >> k) & 0xffu) <= v ? 0xffu << k : 0u;
  return m;
#endif
}
PT_HDI uint32_t BytesAtLeast(uint32_t w, uint32_t v) {
#if PT_IS_GPU_CODE
  return __vcmpgeu4(w, v * 0x01010101u);
#else
  uint32_t m = 0;
  for (uint32_t k = 0; k < 32; k += 8) m |= ((w >> k) & 0xffu) >= v ? 0xffu << k : 0u;
  return m;
#endif
}

// The slots whose boxes hold the ray on each of its parallel axes (WideRay::parallel): byte k
// of half[h] is 0xff where slot 4h + k is kept. On such an axis a box [lo, hi] can hold the ray
// only where lo <= o + t d <= hi, i.e. in quantised units u = (o - origin) / scale within
// [qlo, qhi], widened by the rounding of u (2^-21 |u|) and by how far the ray can drift along
// the axis inside the node: t |d_a| = (|d_a| / |d_m|) t |d_m| for the major axis m, where
// t |d_m| <= |origin_m - o_m| + 255 scale_m (twice that for the roundings of these bounds).
// An exactly zero component (or one whose 1 / d overflows, as the binary test's) drifts 0.
struct SlotKeep {
  uint32_t half[2];
};

// ParallelSlotKeep's bounds on a parallel axis a: the ray's coordinate in the node's units and
// its drift, as [*lo, *hi]. m: the ray's major axis; reach: how far the ray can go along m
// inside the node (see above).
PT_HDI void ParallelBounds(const WideNodeWords& n, const WideRay& r, vec3 absInv, int a, int m,
                           float reach, float* lo, float* hi) {
  // 1 / scale: the exponent byte is 127 + log2(scale), at most 253 for any finite box.
  const uint32_t e = (n.w[3] >> (8 * a)) & 0xffu;
  const float invScale = FloatFromBits((254u - (e < 253u ? e : 253u)) << 23);
  const float u = (WideAxis(r.o, a) - FloatFromBits(n.w[a])) * invScale;
  const float ratio = WideAxis(absInv, m) / WideAxis(absInv, a);  // |d_a| / |d_m|; 0 if inf
  const float pad = fabsf(u) * 0x1p-21f + ratio * reach * invScale;
  *hi = u + pad;
  *lo = u - pad;
}

// The ray's major axis and its reach inside the node, for ParallelBounds.
PT_HDI int ParallelReach(const WideNodeWords& n, const WideRay& r, vec3 absInv, float* reach) {
  const int m = absInv.x <= absInv.y ? (absInv.x <= absInv.z ? 0 : 2)
                                     : (absInv.y <= absInv.z ? 1 : 2);  // the major axis
  const float scaleM = FloatFromBits(((n.w[3] >> (8 * m)) & 0xffu) << 23);
  *reach = 2.0f * (fabsf(FloatFromBits(n.w[m]) - WideAxis(r.o, m)) + 256.0f * scaleM);
  return m;
}

PT_HDI SlotKeep ParallelSlotKeep(const WideNodeWords& n, const WideRay& r) {
  const vec3 absInv(fabsf(r.invDir.x), fabsf(r.invDir.y), fabsf(r.invDir.z));
  float reach;
  const int m = ParallelReach(n, r, absInv, &reach);
  SlotKeep keep{{~0u, ~0u}};
  for (int a = 0; a < 3; ++a) {
    if (((r.parallel >> a) & 1u) == 0) continue;
    float lo, hi;
    ParallelBounds(n, r, absInv, a, m, reach, &lo, &hi);
    if (hi < 0.0f || lo > 255.0f) return SlotKeep{{0u, 0u}};
    // A NaN bound (an overflow) keeps every slot.
    const uint32_t qHi = hi < 255.0f ? uint32_t(floorf(hi)) : 255u;
    const uint32_t qLo = lo > 0.0f ? uint32_t(ceilf(lo)) : 0u;
    for (int h = 0; h < 2; ++h) {
      keep.half[h] &=
          BytesAtMost(n.w[8 + 2 * a + h], qHi) & BytesAtLeast(n.w[14 + 2 * a + h], qLo);
    }
  }
  return keep;
}

#ifdef PT_WIDE_AVX2
// Out of the hot loop: only rays with a parallel axis come here.
__attribute__((noinline, cold)) inline __m256i ParallelSlotKeepAvx2(const WideBvhNode* node,
                                                                      const WideRay& r) {
  const SlotKeep keep = ParallelSlotKeep(LoadWideNode(node), r);
  const __m128i bytes = _mm_setr_epi32(int(keep.half[0]), int(keep.half[1]), 0, 0);
  return _mm256_cvtepi8_epi32(bytes);  // 0xff -> all ones
}
#endif

#ifdef PT_WIDE_AVX2
// x86-64-v3 hosts: the node's eight slots in one pass of 8-lane instructions, its per-node
// constants three axes at once, and the hit slots' mask bits decoded in the vector lanes.
// Fused multiply-adds as on the GPU (kWideSlack's bound covers both roundings).
inline __attribute__((always_inline)) uint32_t IntersectWideChildrenAvx2(const WideBvhNode* node,
                                                                         const WideRay& r,
                                                                         float tMax) {
  const char* bytes = reinterpret_cast<const char*>(node);
  const __m128 head = _mm_load_ps(reinterpret_cast<const float*>(node));  // px py pz | e
  const __m128 o = r.oV, invDir = r.invDirV;
  const __m128i exps = _mm_cvtepu8_epi32(_mm_shuffle_epi32(_mm_castps_si128(head), 0xff));
  const __m128 adj = _mm_mul_ps(_mm_castsi128_ps(_mm_slli_epi32(exps, 23)), invDir);
  const __m128 a = _mm_mul_ps(_mm_sub_ps(head, o), invDir);
  const __m128 absA = _mm_andnot_ps(_mm_set1_ps(-0.0f), a);
  const __m128 e = _mm_mul_ps(_mm_set1_ps(kWideSlack), absA);
  const __m128 nearD = _mm_sub_ps(a, e), farD = _mm_add_ps(a, e);
  __m256 t0 = _mm256_setzero_ps(), t1 = _mm256_set1_ps(tMax);
  auto quantised = [&](uint32_t word) {
    const __m128i q = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(bytes + 4 * word));
    return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(q));
  };
  auto lane = [](__m128 v, int k) {
    return _mm256_broadcastss_ps(_mm_permutevar_ps(v, _mm_set1_epi32(k)));
  };
  for (int axis = 0; axis < 3; ++axis) {
    const __m256 adjA = lane(adj, axis);
    t0 = _mm256_max_ps(_mm256_fmadd_ps(quantised(r.nearWord[axis]), adjA, lane(nearD, axis)), t0);
    t1 = _mm256_min_ps(_mm256_fmadd_ps(quantised(r.farWord[axis]), adjA, lane(farD, axis)), t1);
  }
  __m256 hit = _mm256_cmp_ps(t0, _mm256_mul_ps(t1, _mm256_set1_ps(kWideFarScale)), _CMP_LE_OQ);
  if (r.parallel != 0)
    hit = _mm256_and_ps(hit, _mm256_castsi256_ps(ParallelSlotKeepAvx2(node, r)));
  // SlotBits4's rule, one slot per lane.
  const __m256i meta = _mm256_cvtepu8_epi32(
      _mm_loadl_epi64(reinterpret_cast<const __m128i*>(bytes + 4 * 6)));
  const __m256i k10 = _mm256_set1_epi32(0x10);
  const __m256i interior = _mm256_cmpeq_epi32(
      _mm256_and_si256(_mm256_and_si256(meta, _mm256_slli_epi32(meta, 1)), k10), k10);
  const __m256i bitIndex = _mm256_and_si256(
      _mm256_xor_si256(meta, _mm256_and_si256(interior, _mm256_set1_epi32(int(r.octInv)))),
      _mm256_set1_epi32(0x1f));
  const __m256i childBits = _mm256_and_si256(_mm256_srli_epi32(meta, 5), _mm256_set1_epi32(7));
  const __m256i bits = _mm256_and_si256(_mm256_sllv_epi32(childBits, bitIndex),
                                        _mm256_castps_si256(hit));
  __m128i x = _mm_or_si128(_mm256_castsi256_si128(bits), _mm256_extracti128_si256(bits, 1));
  x = _mm_or_si128(x, _mm_shuffle_epi32(x, 0x4e));
  x = _mm_or_si128(x, _mm_shuffle_epi32(x, 0xb1));
  return uint32_t(_mm_cvtsi128_si32(x));
}
#elif defined(PT_WIDE_SSE)
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
  SlotKeep keep{{~0u, ~0u}};
  if (r.parallel != 0) keep = ParallelSlotKeep(n, r);
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
    const SlotBits4 slots = SlotBits4::Decode(n.w[6 + half] & keep.half[half], r.octInv);
    for (uint32_t k = 0; k < 4; ++k) hits |= slots.HitBits(k) & (0u - ((mask >> k) & 1u));
  }
  return hits;
}
#endif

// A node's slab constants for one ray (see kWideSlack): t = q * adj + near (entry) or + far.
struct WideNodeFrame {
  float adjX, adjY, adjZ, nearX, nearY, nearZ, farX, farY, farZ;

  PT_HDI_HOT static WideNodeFrame Make(const WideNodeWords& n, const WideRay& r) {
    const float px = FloatFromBits(n.w[0]), py = FloatFromBits(n.w[1]), pz = FloatFromBits(n.w[2]);
    const uint32_t e = n.w[3];
    const float ax = (px - r.o.x) * r.invDir.x, ay = (py - r.o.y) * r.invDir.y,
                az = (pz - r.o.z) * r.invDir.z;
    const float ex = kWideSlack * fabsf(ax), ey = kWideSlack * fabsf(ay),
                ez = kWideSlack * fabsf(az);
    return WideNodeFrame{FloatFromBits((e & 0xffu) << 23) * r.invDir.x,
                         FloatFromBits(((e >> 8) & 0xffu) << 23) * r.invDir.y,
                         FloatFromBits(((e >> 16) & 0xffu) << 23) * r.invDir.z,
                         ax - ex, ay - ey, az - ez, ax + ex, ay + ey, az + ez};
  }
};

// The node test one slot at a time (the GPU's; hosts run it for kNearest). kNearest: also
// *nearestBit = the mask bit of the hit interior child with the smallest entry distance (0:
// none), which closest-hit walks on the GPU visit first (traverse_wide.h).
// kParallel: the ray may have a parallel axis (r.parallel, checked per node: ParallelSlotKeep's
// mask, as the SSE and AVX2 tests); a walk whose ray has none may leave it out (traverse_wide.h:
// the GPU's walk then has no parallel-axis code, which cost it 10-20% even untaken).
template <bool kNearest, bool kParallel = true>
PT_HDI_HOT uint32_t IntersectWideChildrenScalar(const WideNodeWords& n, const WideRay& r,
                                                float tMax, uint32_t* nearestBit) {
  const WideNodeFrame f = WideNodeFrame::Make(n, r);
  SlotKeep keep{{~0u, ~0u}};
  if (kParallel && r.parallel != 0) keep = ParallelSlotKeep(n, r);
  uint32_t hits = 0, nearest = 0;
  float nearestT = tMax;
  for (int half = 0; half < 2; ++half) {
    // qlo words at 8 + 2 axis + half, qhi at 14 + 2 axis + half; swapped where the ray goes down.
    uint32_t loX = n.w[8 + half], hiX = n.w[14 + half];
    uint32_t loY = n.w[10 + half], hiY = n.w[16 + half];
    uint32_t loZ = n.w[12 + half], hiZ = n.w[18 + half];
    const uint32_t qnX = r.neg[0] ? hiX : loX, qfX = r.neg[0] ? loX : hiX;
    const uint32_t qnY = r.neg[1] ? hiY : loY, qfY = r.neg[1] ? loY : hiY;
    const uint32_t qnZ = r.neg[2] ? hiZ : loZ, qfZ = r.neg[2] ? loZ : hiZ;
    // A culled slot's meta is 0: no hit bits, and never the nearest.
    const SlotBits4 slots = SlotBits4::Decode(n.w[6 + half] & keep.half[half], r.octInv);
    for (uint32_t k = 0; k < 4; ++k) {
      float t0 = MulAdd(ByteAsFloat(qnX, k), f.adjX, f.nearX);
      t0 = t0 > 0.0f ? t0 : 0.0f;
      t0 = detail::MaxIgnoreNan(t0, MulAdd(ByteAsFloat(qnY, k), f.adjY, f.nearY));
      t0 = detail::MaxIgnoreNan(t0, MulAdd(ByteAsFloat(qnZ, k), f.adjZ, f.nearZ));
      float t1 = detail::MinIgnoreNan(tMax, MulAdd(ByteAsFloat(qfX, k), f.adjX, f.farX));
      t1 = detail::MinIgnoreNan(t1, MulAdd(ByteAsFloat(qfY, k), f.adjY, f.farY));
      t1 = detail::MinIgnoreNan(t1, MulAdd(ByteAsFloat(qfZ, k), f.adjZ, f.farZ));
      if (t0 <= t1 * kWideFarScale) {
        hits |= slots.HitBits(k);
        if constexpr (kNearest) {
          const uint32_t bit = (slots.bitIndex4 >> (8u * k)) & 0xffu;
          if (bit >= 24u && t0 <= nearestT) {
            nearestT = t0;
            nearest = bit;
          }
        }
      }
    }
  }
  if constexpr (kNearest) *nearestBit = nearest;
  return hits;
}

// Bit mask of the children of `n` that the ray enters within [0, tMax]: interior children at
// bit 24 + (slot ^ octInv), each leaf's primitives at bits [offset, offset + count).
PT_HDI_HOT uint32_t IntersectWideChildren(const WideNodeWords& n, const WideRay& r, float tMax) {
#ifdef PT_WIDE_SSE
  const WideNodeFrame f = WideNodeFrame::Make(n, r);
  const float adj[3] = {f.adjX, f.adjY, f.adjZ}, nearD[3] = {f.nearX, f.nearY, f.nearZ},
              farD[3] = {f.farX, f.farY, f.farZ};
  return IntersectWideChildrenSse(n, r, tMax, adj, nearD, farD);
#else
  return IntersectWideChildrenScalar<false>(n, r, tMax, nullptr);
#endif
}

// What the traversal needs of a visited node: the hit bits and where its children are.
struct WideNodeHits {
  uint32_t hits, childBase, primBase, innerMask;
  uint32_t nearest = 0;  // kNearest: the nearest hit interior child's bit (0: none)
};

// kNearest (the GPU's closest-hit walks): with the nearest hit interior child. Hosts then run
// the scalar test (tests/bvh_wide_test.cpp walks that way); their own walks take the octant
// order, which was faster on the CPU (benchmarks/RESULTS.md, 2026-11-26, third session).
template <bool kNearest = false, bool kParallel = true>
PT_HDI_HOT WideNodeHits TestWideNode(const WideBvhNode* node, const WideRay& r, float tMax) {
#ifdef PT_WIDE_AVX2
  if constexpr (!kNearest) {
    // The fields straight from memory: no copy of the node's words to index into.
    return WideNodeHits{IntersectWideChildrenAvx2(node, r, tMax), node->childBase,
                        node->primBase, node->innerMask};
  }
#endif
  const WideNodeWords n = LoadWideNode(node);
  WideNodeHits h{0u, n.w[4], n.w[5], n.w[3] >> 24};
  if constexpr (kNearest) {
    h.hits = IntersectWideChildrenScalar<true, kParallel>(n, r, tMax, &h.nearest);
  } else if constexpr (!kParallel) {
    h.hits = IntersectWideChildrenScalar<false, false>(n, r, tMax, nullptr);
  } else {
    h.hits = IntersectWideChildren(n, r, tMax);
  }
  return h;
}

}  // namespace detail
}  // namespace pt
