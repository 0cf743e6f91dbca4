#include "renderer/sampling/sampler.h"

#include <cstring>

#include "renderer/sampling/hash.h"
#include "renderer/sampling/pcg.h"
#include "renderer/sampling/sobol.h"

namespace tex::sampling {

Sampler::Sampler(SamplerKind kind, uint64_t seed, const PixelGrid& grid) : Sampler(kind, seed) {
  hasGrid_ = grid.valid();
  if (hasGrid_) pixels_ = PixelSampleMap(grid, filmScrambleSeeds_);
}

Sampler::Sampler(SamplerKind kind, uint64_t seed) : kind_(kind), seed_(seed) {
  filmScrambleSeeds_[0] = sobolScrambleSeed(seed, 0, 0);
  filmScrambleSeeds_[1] = sobolScrambleSeed(seed, 1, 0);
  auto seeds = std::make_shared<std::array<uint32_t, kSobolDimensions>>();
  for (int d = 0; d < kSobolDimensions; ++d) (*seeds)[size_t(d)] = sobolScrambleSeed(seed, d, 0);
  scrambleSeeds_ = std::move(seeds);
}

namespace {

// tables[d][1][b1] ^ tables[d][2][b2] ^ tables[d][3][b3] for every fast dimension d, for the
// calling thread's latest block of 256 indices (indexHigh = index >> 8, below 2^24).
const uint32_t* highBytesXorOfBlock(uint32_t indexHigh) {
  struct Block {
    uint32_t indexHigh = ~0u;  // no block yet (index >> 8 of a 32-bit index is below 2^24)
    uint32_t xors[kSobolByteTableDimensions] = {};
  };
  thread_local Block block;
  if (block.indexHigh != indexHigh) {
    const uint32_t b1 = indexHigh & 0xffu, b2 = (indexHigh >> 8) & 0xffu, b3 = indexHigh >> 16;
    for (int d = 0; d < kSobolByteTableDimensions; ++d) {
      const uint32_t(*t)[256] = kSobolReversedByteTables[d];
      block.xors[d] = t[1][b1] ^ t[2][b2] ^ t[3][b3];
    }
    block.indexHigh = indexHigh;
  }
  return block.xors;
}

}  // namespace

IndexSampler::IndexSampler(const Sampler& sampler, uint64_t index) : sampler_(sampler) {
  if (sampler.hasGrid_) {
    const PixelSample ps = sampler.pixels_.map(index);
    index_ = ps.sobolIndex;
    film_ = sampler.pixelFilmPosition(ps);
    if (sampler.kind_ == SamplerKind::Sobol) {
      padded_ = true;
      pixelKey_ = sampler.pixelKeyOf(ps);
      sampleInPixel_ = uint32_t(ps.sampleInPixel);
    }
  } else {
    index_ = index;
    film_ = sampler.filmPosition(index);
  }
  fast_ = !padded_ && sampler.kind_ == SamplerKind::Sobol && (index_ >> 32) == 0;
  lowByte_ = uint32_t(index_) & 0xffu;
  seeds_ = sampler.scrambleSeeds_->data();
  // Uninitialised otherwise: get() then never reads it.
  if (fast_) std::memcpy(highBytesXor_, highBytesXorOfBlock(uint32_t(index_) >> 8), sizeof highBytesXor_);
}

uint32_t Sampler::getBitsAt(uint64_t index, int dimension) const {
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
