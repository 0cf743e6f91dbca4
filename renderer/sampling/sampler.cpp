#include "renderer/sampling/sampler.h"

#include "renderer/sampling/hash.h"
#include "renderer/sampling/pcg.h"
#include "renderer/sampling/sobol.h"

namespace tex::sampling {

Sampler::Sampler(SamplerKind kind, uint64_t seed) : kind_(kind), seed_(seed) {
  filmScrambleSeeds_[0] = sobolScrambleSeed(seed, 0, 0);
  filmScrambleSeeds_[1] = sobolScrambleSeed(seed, 1, 0);
  auto seeds = std::make_shared<std::array<uint32_t, kSobolDimensions>>();
  for (int d = 0; d < kSobolDimensions; ++d) (*seeds)[size_t(d)] = sobolScrambleSeed(seed, d, 0);
  scrambleSeeds_ = std::move(seeds);
}

uint32_t Sampler::getBits(uint64_t index, int dimension) const {
  if (kind_ == SamplerKind::Sobol) return sobolOwenBits(seed_, index, dimension);
  return randomBits(seed_, index, dimension);
}


FilmPosition Sampler::filmPositionGeneral(uint64_t index) const {
  if (kind_ == SamplerKind::Sobol) {
    uint32_t x = 0, y = 0;
    sobolOwenFirstTwo(seed_, index, x, y);
    return {bitsToUnitFloat(x), bitsToUnitFloat(y)};
  }
  // One PCG stream per index: dimensions 0 and 1 are its first two outputs.
  Pcg32 rng(hashWords(seed_, index), seed_);
  const float x = rng.nextFloat();
  return {x, rng.nextFloat()};
}

const char* samplerName(SamplerKind kind) { return kind == SamplerKind::Sobol ? "sobol" : "random"; }

std::optional<SamplerKind> parseSamplerKind(const std::string& name) {
  if (name == "sobol") return SamplerKind::Sobol;
  if (name == "random" || name == "pcg") return SamplerKind::Random;
  return std::nullopt;
}

}  // namespace tex::sampling
