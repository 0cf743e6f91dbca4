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

// Nested uniform scramble of 32 fixed-point bits (bit k of the result depends only on bits
// more significant than k and on the seed).
uint32_t owenScramble(uint32_t bits, uint32_t seed);

// The per-dimension scramble seed for a sampler seed and the index's high word.
uint32_t sobolScrambleSeed(uint64_t seed, int dimension, uint32_t indexHigh);

// Scrambled Sobol coordinate as 32 fixed-point bits. Dimensions >= kSobolDimensions fall
// back to hashed random bits (documented in docs/runtime.md).
uint32_t sobolOwenBits(uint64_t seed, uint64_t index, int dimension);

// Scrambled Sobol coordinate in [0,1).
float sobolOwen(uint64_t seed, uint64_t index, int dimension);

// The first two scrambled dimensions at once (the film position), via byte tables.
void sobolOwenFirstTwo(uint64_t seed, uint64_t index, uint32_t& bits0, uint32_t& bits1);

}  // namespace tex::sampling
