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

// Sobol dimension 1: the generator matrix is Pascal's triangle mod 2, whose columns follow
// v <- v ^ (v >> 1) from the top bit (dimension 0 is the bit reversal, the van der Corput
// sequence).
PT_HDI uint32_t SobolDimension1(uint32_t index) {
  uint32_t v = 1u << 31, result = 0;
  for (; index != 0; index >>= 1, v ^= v >> 1) result ^= v & (0u - (index & 1u));
  return result;
}

// The Owen-scrambled Sobol pair of sample `index` as 0.32 fixed point. seeds: x shuffles
// the index (an Owen scramble of the index's bits, which maps each aligned block of 2^k
// indices onto another such block: a (0,2)-sequence's blocks are all (0,k,2)-nets), y and z
// scramble the two coordinates.
PT_HDI glm::uvec2 SobolBurleyPair(uint32_t index, glm::uvec3 seeds) {
  const uint32_t i = NestedUniformScramble(index, seeds.x);
  // NestedUniformScramble(ReverseBits32(i)) with the two reversals cancelled.
  const uint32_t x = ReverseBits32(LaineKarrasPermutation(i, seeds.y));
  return glm::uvec2(x, NestedUniformScramble(SobolDimension1(i), seeds.z));
}

}  // namespace pt
