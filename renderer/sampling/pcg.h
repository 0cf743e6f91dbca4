// PCG32 (O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
// Algorithms for Random Number Generation", 2014): the random baseline sampler. The
// stateless form randomUniform(seed, index, dimension) seeds one stream per (seed, index)
// and jumps ahead `dimension` steps, so it is a pure function like the Sobol sampler.
#pragma once
#include <cstdint>

namespace tex::sampling {

class Pcg32 {
 public:
  static constexpr uint64_t kMultiplier = 6364136223846793005ull;

  Pcg32(uint64_t initState, uint64_t streamId);

  uint32_t nextBits();
  float nextFloat();  // [0,1)
  // Advances the state by `delta` steps in O(log delta).
  void advance(uint64_t delta);

 private:
  uint64_t state_ = 0;
  uint64_t increment_ = 1;
};

// 32 random bits for (seed, index, dimension).
uint32_t randomBits(uint64_t seed, uint64_t index, int dimension);
// A uniform number in [0,1) for (seed, index, dimension).
float randomUniform(uint64_t seed, uint64_t index, int dimension);

}  // namespace tex::sampling
