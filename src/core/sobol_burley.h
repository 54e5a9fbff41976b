// Owen-scrambled, padded Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling",
// JCGT 9(4)): the first two Sobol dimensions, with the point index shuffled and each
// coordinate scrambled by hash-based nested uniform (Owen) scrambles. Every power-of-two
// prefix of the indices 0, 1, 2, ... is a (0,2)-net of the pair; independent seeds per pair
// decorrelate pairs and pixels ("padding"). Plain integer arithmetic, no tables: the same
// bits on the CPU and the GPU.
#pragma once

#include "src/core/math.h"

namespace pt {

PT_HDI uint32_t ReverseBits32(uint32_t x) {
#if PT_IS_GPU_CODE
  return __brev(x);
#else
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x >> 8) & 0x00ff00ffu);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
  x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
  return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
#endif
}

// A hashed permutation of 32-bit words in which bit i of the result depends only on bits
// 0..i of x (Laine and Karras 2011; the constants are the ones Burley's paper gives): adding
// the seed carries upwards, and x ^= x * even only mixes lower bits into higher ones. Each
// step is invertible, so the whole is a bijection.
PT_HDI uint32_t LaineKarrasPermutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Nested uniform scrambling of a 0.32 fixed-point number: in the bit-reversed domain, each
// bit is flipped by a hash of the bits above it, which is Owen's scramble (the interval a
// point lies in at each level is permuted as a whole, so nets stay nets).
PT_HDI uint32_t NestedUniformScramble(uint32_t x, uint32_t seed) {
  return ReverseBits32(LaineKarrasPermutation(ReverseBits32(x), seed));
}

// Sobol dimension 1 before its final bit reversal. Its generator matrix is Pascal's triangle
// mod 2 (direction numbers v <- v ^ (v >> 1) from the top bit): bit i of the result is the
// parity of sum_j C(j, i) index_j, the coefficients of f(t + 1) for f(t) = sum_j index_j t^j
// over GF(2). With f = lo + t^s hi and (t + 1)^s = t^s + 1 for s a power of two, the shift
// is done on halves, then lo ^= hi: five masked xor-shifts instead of a loop over 32 bits.
PT_HDI uint32_t PascalShiftBits(uint32_t index) {
  index ^= (index >> 1) & 0x55555555u;
  index ^= (index >> 2) & 0x33333333u;
  index ^= (index >> 4) & 0x0f0f0f0fu;
  index ^= (index >> 8) & 0x00ff00ffu;
  return index ^ (index >> 16);
}

// Sobol dimension 1 as 0.32 fixed point (dimension 0 is the bit reversal of the index, the
// van der Corput sequence).
PT_HDI uint32_t SobolDimension1(uint32_t index) { return ReverseBits32(PascalShiftBits(index)); }

// The Owen-scrambled Sobol pair of sample `index` as 0.32 fixed point. seeds: x shuffles
// the index (an Owen scramble of the index's bits, which maps each aligned block of 2^k
// indices onto another such block: a (0,2)-sequence's blocks are all (0,k,2)-nets), y and z
// scramble the two coordinates.
PT_HDI glm::uvec2 SobolBurleyPair(uint32_t index, glm::uvec3 seeds) {
  const uint32_t i = NestedUniformScramble(index, seeds.x);
  // NestedUniformScramble of ReverseBits32(i) and of SobolDimension1(i), with the reversals
  // into the scrambles' domain cancelled.
  return glm::uvec2(ReverseBits32(LaineKarrasPermutation(i, seeds.y)),
                    ReverseBits32(LaineKarrasPermutation(PascalShiftBits(i), seeds.z)));
}

}  // namespace pt
