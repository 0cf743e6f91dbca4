#include "renderer/sampling/sobol.h"

#include "renderer/sampling/hash.h"

namespace tex::sampling {

namespace {
const uint32_t (*buildReversedByteTables())[4][256] {
  static uint32_t tables[kSobolByteTableDimensions][4][256];
  for (int d = 0; d < kSobolByteTableDimensions; ++d)
    for (int b = 0; b < 4; ++b)
      for (uint32_t v = 0; v < 256; ++v) tables[d][b][v] = reverseBits32(sobolBits(v << (8 * b), d));
  return tables;
}
const uint16_t* buildReverse12() {
  static uint16_t table[4096];
  for (uint32_t v = 0; v < 4096; ++v) table[v] = uint16_t(reverseBits32(v) >> 20);
  return table;
}
}  // namespace

const uint32_t (*const kSobolReversedByteTables)[4][256] = buildReversedByteTables();
const uint16_t* const kReverse12Bits = buildReverse12();

uint32_t sobolScrambleSeed(uint64_t seed, int dimension, uint32_t indexHigh) {
  return uint32_t(hashWords(seed, uint64_t(dimension), indexHigh) >> 32);
}

uint32_t sobolOwenBits(uint64_t seed, uint64_t index, int dimension) {
  const uint32_t high = uint32_t(index >> 32);
  if (dimension >= kSobolDimensions || dimension < 0) {
    return uint32_t(hashWords(seed ^ 0x5eed5eed5eedull, index, uint64_t(dimension)) >> 32);
  }
  return owenScramble(sobolBitsFast(uint32_t(index), dimension), sobolScrambleSeed(seed, dimension, high));
}

float sobolOwen(uint64_t seed, uint64_t index, int dimension) {
  return bitsToUnitFloat(sobolOwenBits(seed, index, dimension));
}

void sobolOwenFirstTwo(uint64_t seed, uint64_t index, uint32_t& bits0, uint32_t& bits1) {
  uint32_t x = 0, y = 0;
  sobolFirstTwoReversed(uint32_t(index), x, y);
  const uint32_t high = uint32_t(index >> 32);
  bits0 = reverseBits32(laineKarrasPermutation(x, sobolScrambleSeed(seed, 0, high)));
  bits1 = reverseBits32(laineKarrasPermutation(y, sobolScrambleSeed(seed, 1, high)));
}

}  // namespace tex::sampling
