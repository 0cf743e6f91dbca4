#include "renderer/sampling/sobol.h"

#include <array>

#include "renderer/sampling/hash.h"

namespace tex::sampling {

namespace {

inline uint32_t reverseBits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
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

// XOR tables for the first two dimensions: table[d][byte position][byte value].
struct FirstTwoTables {
  std::array<std::array<std::array<uint32_t, 256>, 4>, 2> xorOf{};
  FirstTwoTables() {
    for (int d = 0; d < 2; ++d)
      for (int p = 0; p < 4; ++p)
        for (uint32_t v = 0; v < 256; ++v) xorOf[d][p][v] = sobolBits(v << (8 * p), d);
  }
};
const FirstTwoTables& firstTwoTables() {
  static const FirstTwoTables tables;
  return tables;
}

}  // namespace

uint32_t owenScramble(uint32_t bits, uint32_t seed) {
  return reverseBits(laineKarrasPermutation(reverseBits(bits), seed));
}

uint32_t sobolScrambleSeed(uint64_t seed, int dimension, uint32_t indexHigh) {
  return uint32_t(hashWords(seed, uint64_t(dimension), indexHigh) >> 32);
}

uint32_t sobolOwenBits(uint64_t seed, uint64_t index, int dimension) {
  const uint32_t high = uint32_t(index >> 32);
  if (dimension >= kSobolDimensions || dimension < 0) {
    return uint32_t(hashWords(seed ^ 0x5eed5eed5eedull, index, uint64_t(dimension)) >> 32);
  }
  return owenScramble(sobolBits(uint32_t(index), dimension), sobolScrambleSeed(seed, dimension, high));
}

float sobolOwen(uint64_t seed, uint64_t index, int dimension) {
  return bitsToUnitFloat(sobolOwenBits(seed, index, dimension));
}

void sobolOwenFirstTwo(uint64_t seed, uint64_t index, uint32_t& bits0, uint32_t& bits1) {
  const FirstTwoTables& t = firstTwoTables();
  const uint32_t low = uint32_t(index);
  const uint32_t b0 = low & 0xffu, b1 = (low >> 8) & 0xffu, b2 = (low >> 16) & 0xffu, b3 = low >> 24;
  const uint32_t x = t.xorOf[0][0][b0] ^ t.xorOf[0][1][b1] ^ t.xorOf[0][2][b2] ^ t.xorOf[0][3][b3];
  const uint32_t y = t.xorOf[1][0][b0] ^ t.xorOf[1][1][b1] ^ t.xorOf[1][2][b2] ^ t.xorOf[1][3][b3];
  const uint32_t high = uint32_t(index >> 32);
  bits0 = owenScramble(x, sobolScrambleSeed(seed, 0, high));
  bits1 = owenScramble(y, sobolScrambleSeed(seed, 1, high));
}

}  // namespace tex::sampling
