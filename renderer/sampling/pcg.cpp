#include "renderer/sampling/pcg.h"

#include "renderer/sampling/hash.h"

namespace tex::sampling {

Pcg32::Pcg32(uint64_t initState, uint64_t streamId) {
  increment_ = (streamId << 1u) | 1u;
  state_ = 0;
  nextBits();
  state_ += initState;
  nextBits();
}

uint32_t Pcg32::nextBits() {
  const uint64_t old = state_;
  state_ = old * kMultiplier + increment_;
  const uint32_t xorShifted = uint32_t(((old >> 18u) ^ old) >> 27u);
  const uint32_t rot = uint32_t(old >> 59u);
  return (xorShifted >> rot) | (xorShifted << ((~rot + 1u) & 31));
}

float Pcg32::nextFloat() { return bitsToUnitFloat(nextBits()); }

void Pcg32::advance(uint64_t delta) {
  // Brown, "Random number generation with arbitrary strides" (1994), as in pcg_basic.c.
  uint64_t curMult = kMultiplier, curPlus = increment_, accMult = 1, accPlus = 0;
  while (delta > 0) {
    if (delta & 1) {
      accMult *= curMult;
      accPlus = accPlus * curMult + curPlus;
    }
    curPlus = (curMult + 1) * curPlus;
    curMult *= curMult;
    delta /= 2;
  }
  state_ = accMult * state_ + accPlus;
}

uint32_t randomBits(uint64_t seed, uint64_t index, int dimension) {
  Pcg32 rng(hashWords(seed, index), seed);
  rng.advance(uint64_t(uint32_t(dimension)));
  return rng.nextBits();
}

float randomUniform(uint64_t seed, uint64_t index, int dimension) {
  return bitsToUnitFloat(randomBits(seed, index, dimension));
}

}  // namespace tex::sampling
