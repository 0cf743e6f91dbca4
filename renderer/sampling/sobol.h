// Owen-scrambled Sobol points as a pure function of (seed, sample index, dimension).
//
// Generator matrices: Joe-Kuo new-joe-kuo-6.21201 direction numbers (sobol_matrices.cpp),
// 32-bit, for kSobolDimensions dimensions. Scrambling: the hash-based nested uniform
// (Owen) scramble of Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020, built
// on the Laine-Karras permutation; it preserves the (0,m,2)-net property of every pair of
// leading dimensions. Each dimension gets its own scramble seed hash(seed, dimension); index
// bits above 32 select an independent scramble, so each block of 2^32 indices is itself a
// scrambled Sobol sequence.
#pragma once
#include <cstdint>

namespace tex::sampling {

inline constexpr int kSobolDimensions = 1024;
extern const uint32_t kSobolMatrices[kSobolDimensions][32];

// Unscrambled Sobol point: 32 fixed-point bits of coordinate `dimension` of point `index`.
inline uint32_t sobolBits(uint32_t index, int dimension) {
  const uint32_t* columns = kSobolMatrices[dimension];
  uint32_t bits = 0;
  for (int k = 0; index != 0; index >>= 1, ++k) bits ^= columns[k] & (0u - (index & 1u));
  return bits;
}

inline uint32_t reverseBits32(uint32_t x) {
  x = __builtin_bswap32(x);  // bytes, then bits within bytes
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
}

// The same product by bytes, bit-reversed: for the first kSobolByteTableDimensions dimensions
// (those every path uses), four lookups in per-dimension tables of the XOR of the reversed
// columns selected by each byte value (reversal commutes with XOR), instead of a loop over the
// index's bits (256 KB of tables, built at start-up). Reversed because the Owen scramble works
// on reversed bits: the sampler's fast path then never reverses its input.
inline constexpr int kSobolByteTableDimensions = 64;
extern const uint32_t (*const kSobolReversedByteTables)[4][256];
inline uint32_t sobolReversedBitsFast(uint32_t index, int dimension) {
  const uint32_t(*t)[256] = kSobolReversedByteTables[dimension];
  return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}
inline uint32_t sobolBitsFast(uint32_t index, int dimension) {
  if (dimension >= kSobolByteTableDimensions) return sobolBits(index, dimension);
  return reverseBits32(sobolReversedBitsFast(index, dimension));
}

// Burley 2020, listing 2 (the improved Laine-Karras hash). Every step maps bit k from bits
// <= k only, which is what makes the reversed application a nested (Owen) scramble.
inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Nested uniform scramble of 32 fixed-point bits (bit k of the result depends only on bits
// more significant than k and on the seed).
inline uint32_t owenScramble(uint32_t bits, uint32_t seed) {
  return reverseBits32(laineKarrasPermutation(reverseBits32(bits), seed));
}

// Bits 0-23 of x reversed into 24 bits (bit 0 becomes bit 23): reverseBits32(x) >> 8, the
// top 24 bits a [0,1) float keeps, by two lookups in a 12-bit reversal table (8 KB).
extern const uint16_t* const kReverse12Bits;
inline uint32_t reverseLow24(uint32_t x) {
  return (uint32_t(kReverse12Bits[x & 0xfffu]) << 12) | uint32_t(kReverse12Bits[(x >> 12) & 0xfffu]);
}

// The per-dimension scramble seed for a sampler seed and the index's high word.
uint32_t sobolScrambleSeed(uint64_t seed, int dimension, uint32_t indexHigh);

// Scrambled Sobol coordinate as 32 fixed-point bits. Dimensions >= kSobolDimensions fall
// back to hashed random bits (documented in docs/runtime.md).
uint32_t sobolOwenBits(uint64_t seed, uint64_t index, int dimension);

// Scrambled Sobol coordinate in [0,1).
float sobolOwen(uint64_t seed, uint64_t index, int dimension);

// The first two unscrambled dimensions at once, bit-reversed (the form the scramble works
// on), without the matrices: dimension 0 is the van der Corput sequence, so reversed it is the
// index itself; dimension 1's generator is the Pascal matrix mod 2, so by Lucas's theorem bit k
// of the reversed point is the XOR of the index bits j whose positions contain k's (j & k ==
// k), a superset transform in five shift-and-xor steps. (Tested against the matrices.)
inline void sobolFirstTwoReversed(uint32_t index, uint32_t& reversed0, uint32_t& reversed1) {
  uint32_t y = index;
  y ^= (y >> 1) & 0x55555555u;
  y ^= (y >> 2) & 0x33333333u;
  y ^= (y >> 4) & 0x0f0f0f0fu;
  y ^= (y >> 8) & 0x00ff00ffu;
  y ^= (y >> 16) & 0x0000ffffu;
  reversed0 = index;
  reversed1 = y;
}

// The first two scrambled dimensions at once (the film position).
void sobolOwenFirstTwo(uint64_t seed, uint64_t index, uint32_t& bits0, uint32_t& bits1);

}  // namespace tex::sampling
