#include "renderer/sampling/sobol.h"

#include <array>

#include "renderer/sampling/hash.h"

namespace tex::sampling {

namespace {

// XOR tables for the first two dimensions, bit-reversed: table[d][byte position][byte value].
struct FirstTwoTables {
  std::array<std::array<std::array<uint32_t, 256>, 4>, 2> xorOf{};
  FirstTwoTables() {
    for (int d = 0; d < 2; ++d)
      for (int p = 0; p < 4; ++p)
        for (uint32_t v = 0; v < 256; ++v) xorOf[d][p][v] = reverseBits32(sobolBits(v << (8 * p), d));
  }
};
const FirstTwoTables& firstTwoTables() {
  static const FirstTwoTables tables;
  return tables;
}

}  // namespace

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

void sobolFirstTwoReversed(uint32_t low, uint32_t& x, uint32_t& y) {
  static const FirstTwoTables& t = firstTwoTables();
  const uint32_t b0 = low & 0xffu, b1 = (low >> 8) & 0xffu, b2 = (low >> 16) & 0xffu, b3 = low >> 24;
  x = t.xorOf[0][0][b0] ^ t.xorOf[0][1][b1] ^ t.xorOf[0][2][b2] ^ t.xorOf[0][3][b3];
  y = t.xorOf[1][0][b0] ^ t.xorOf[1][1][b1] ^ t.xorOf[1][2][b2] ^ t.xorOf[1][3][b3];
}

void sobolOwenFirstTwo(uint64_t seed, uint64_t index, uint32_t& bits0, uint32_t& bits1) {
  uint32_t x = 0, y = 0;
  sobolFirstTwoReversed(uint32_t(index), x, y);
  const uint32_t high = uint32_t(index >> 32);
  bits0 = reverseBits32(laineKarrasPermutation(x, sobolScrambleSeed(seed, 0, high)));
  bits1 = reverseBits32(laineKarrasPermutation(y, sobolScrambleSeed(seed, 1, high)));
}

}  // namespace tex::sampling
