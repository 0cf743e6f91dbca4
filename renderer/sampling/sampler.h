// The sampler a kernel sees: a pure function of (seed, sample index, dimension) in [0,1).
// Dimension conventions (shared by every kernel so that the film is stratified):
//   0, 1  film position x, y (the global index is the film stratum: the first 2^m indices of
//         the Sobol sampler form a (0,m,2)-net over the whole image);
//   2     wavelength group rotation;
//   3...  the kernel's own dimensions (kFirstKernelDimension).
#pragma once
#include <cmath>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "renderer/sampling/hash.h"
#include "renderer/sampling/padded_sobol.h"
#include "renderer/sampling/pixel_grid.h"
#include "renderer/sampling/sobol.h"

namespace tex::sampling {

enum class SamplerKind : uint8_t { Sobol = 0, Random = 1 };

inline constexpr int kFilmDimensionX = 0;
inline constexpr int kFilmDimensionY = 1;
inline constexpr int kWavelengthDimension = 2;
inline constexpr int kFirstKernelDimension = 3;

struct FilmPosition {
  float x = 0, y = 0;  // [0,1)^2, x to the right, y downwards
};

// The Sobol fast path's last step: bit-reversed Sobol bits, Owen-scrambled, as a [0,1) float
// (bitsToUnitFloat(owenScramble(bits, seed)) with neither bit reversal done word-wide: only the
// float's 24 bits are reversed back).
inline float scrambledReversedToUnitFloat(uint32_t reversedBits, uint32_t seed) {
  return float(reverseLow24(laineKarrasPermutation(reversedBits, seed))) * 0x1p-24f;
}

class Sampler {
 public:
  Sampler(SamplerKind kind, uint64_t seed);
  // A sampler of a render's pixel grid (pixel_grid.h): every W H consecutive indices give each
  // pixel one sample, the film-wide sequence's point in its cell. Without a grid the sample
  // index is the point's index in one film-wide sequence (kernels over the unit square).
  Sampler(SamplerKind kind, uint64_t seed, const PixelGrid& grid);

  // Coordinate `dimension` of sample `index`, in [0,1).
  float get(uint64_t index, int dimension) const {
    if (hasGrid_) {
      const PixelSample ps = pixels_.map(index);
      if (padded(dimension)) return bitsToUnitFloat(paddedBitsOf(ps, dimension));
      return getAt(ps.sobolIndex, dimension);
    }
    return getAt(index, dimension);
  }
  // Coordinate `dimension` of point `pointIndex` of the sequence itself (no pixel mapping).
  float getAt(uint64_t index, int dimension) const {
    if (kind_ == SamplerKind::Sobol && (index >> 32) == 0) {
      // The tables give the reversed Sobol bits (scrambledReversedToUnitFloat).
      if (unsigned(dimension) < unsigned(kSobolByteTableDimensions))
        return scrambledReversedToUnitFloat(sobolReversedBitsFast(uint32_t(index), dimension),
                                            (*scrambleSeeds_)[size_t(dimension)]);
      if (unsigned(dimension) < unsigned(kSobolDimensions))
        return bitsToUnitFloat(owenScramble(sobolBits(uint32_t(index), dimension), (*scrambleSeeds_)[size_t(dimension)]));
    }
    return bitsToUnitFloat(getBitsAt(index, dimension));
  }
  // 32 fixed-point bits of the same coordinate (for exact stratification tests).
  uint32_t getBits(uint64_t index, int dimension) const {
    if (!hasGrid_) return getBitsAt(index, dimension);
    const PixelSample ps = pixels_.map(index);
    return padded(dimension) ? paddedBitsOf(ps, dimension) : getBitsAt(ps.sobolIndex, dimension);
  }
  uint32_t getBitsAt(uint64_t pointIndex, int dimension) const;
  // Dimensions 0 and 1: where sample `index` lands on the film (inline: every kernel calls it
  // once per index).
  FilmPosition filmPosition(uint64_t index) const {
    if (hasGrid_) return pixelFilmPosition(pixels_.map(index));
    if (kind_ == SamplerKind::Sobol && (index >> 32) == 0) return sobolFilmPosition(uint32_t(index));
    return filmPositionGeneral(index);
  }

  SamplerKind kind() const { return kind_; }
  uint64_t seed() const { return seed_; }
  bool hasPixelGrid() const { return hasGrid_; }

 private:
  friend class IndexSampler;
  FilmPosition filmPositionGeneral(uint64_t index) const;
  // Dimensions from 2 of a Sobol render are padded per pixel (padded_sobol.h).
  bool padded(int dimension) const { return hasGrid_ && kind_ == SamplerKind::Sobol && dimension >= kWavelengthDimension; }
  uint64_t pixelKeyOf(const PixelSample& ps) const {
    return paddedPixelKey(seed_, ps.x + pixels_.grid().originX, ps.y + pixels_.grid().originY);
  }
  uint32_t paddedBitsOf(const PixelSample& ps, int dimension) const {
    const uint64_t key = pixelKeyOf(ps);
    return paddedBits(key, paddedGroupIndex(key, uint32_t(ps.sampleInPixel), dimension / kPaddedGroupSize), dimension);
  }
  // The film position of a mapped sample: its pixel plus the offset of dimensions 0 and 1.
  // The point's position within its cell of 2^r x 2^r (the fraction of 2^r times its film
  // coordinates) placed in the sample's pixel: exactly the point itself when it lies in that
  // cell (Sobol indices below 2^32; above, the scramble changes per 2^32 block and only the
  // offset is kept). At square power-of-two resolutions without a crop this is the film-wide
  // position bit for bit (every step is exact in float).
  FilmPosition pixelFilmPosition(const PixelSample& ps) const {
    const FilmPosition point = ps.sobolIndex >> 32 == 0 && kind_ == SamplerKind::Sobol ? sobolFilmPosition(uint32_t(ps.sobolIndex))
                                                                                      : filmPositionGeneral(ps.sobolIndex);
    const float cells = float(uint32_t(1) << pixels_.cellBits());
    const float cx = point.x * cells, cy = point.y * cells;
    const float ox = cx - float(int(cx)), oy = cy - float(int(cy));  // in [0, 1)
    // Times the reciprocal (exact for power-of-two sizes; a division each was in the profile).
    const float fx = std::min((float(ps.x) + ox) * pixels_.inverseWidth(), 0x1.fffffep-1f);
    const float fy = std::min((float(ps.y) + oy) * pixels_.inverseHeight(), 0x1.fffffep-1f);
    return {pixels_.widthExact() ? fx : inPixel(fx, ps.x, pixels_.grid().width),
            pixels_.heightExact() ? fy : inPixel(fy, ps.y, pixels_.grid().height)};
  }
  // The film bins a position f by int(f * size) (film.cpp). At sizes that are not powers of two
  // the rounded 1/size can put (x + o) / size just below x / size for o = 0, or a rounded x + o
  // onto x + 1: the sample then landed in a neighbouring pixel, which got one more (a 40000-wide
  // image had pixels of 2 to 6 samples at 4 spp). Such positions move by ulps into their pixel.
  static float inPixel(float f, int pixel, int size) {
    const float fs = float(size);
    while (int(f * fs) < pixel) f = std::nextafter(f, 1.0f);
    while (f > 0.0f && int(f * fs) > pixel) f = std::nextafter(f, 0.0f);
    return f;
  }
  FilmPosition sobolFilmPosition(uint32_t index) const {
    uint32_t x = 0, y = 0;
    sobolFirstTwoReversed(index, x, y);
    return {bitsToUnitFloat(reverseBits32(laineKarrasPermutation(x, filmScrambleSeeds_[0]))),
            bitsToUnitFloat(reverseBits32(laineKarrasPermutation(y, filmScrambleSeeds_[1])))};
  }
  bool hasGrid_ = false;
  PixelSampleMap pixels_;
  SamplerKind kind_;
  uint64_t seed_;
  uint32_t filmScrambleSeeds_[2];  // Sobol scramble seeds of dimensions 0, 1 for indices < 2^32
  // Every dimension's scramble seed for indices < 2^32 (shared: samplers are copied freely).
  std::shared_ptr<const std::array<uint32_t, kSobolDimensions>> scrambleSeeds_;
};

// The coordinates of one sample index, for a kernel that reads many dimensions of it (the path
// tracer reads about 30 per path): get(d) == Sampler::get(index, d), bit for bit. In the Sobol
// fast path the index's bytes 1-3 pick the same rows of every dimension's byte tables and
// change only once per 256 indices, so their XOR per dimension is computed once per thread and
// block of 256 indices (and copied here), leaving one lookup per coordinate instead of four
// spread over a 4 KB table.
class IndexSampler {
 public:
  // `index` is the sample index (mapped to its pixel and Sobol point when the sampler has a
  // pixel grid).
  IndexSampler(const Sampler& sampler, uint64_t index);
  float get(int dimension) const {
    if (padded_ && dimension >= kWavelengthDimension) {  // reverseLow24: the float's 24 bits, as the fast path
      const int group = dimension / kPaddedGroupSize;
      if (group < kCachedGroups) {
        if (!(groupsKnown_ >> group & 1u)) fillGroup(group);
        const int j = dimension % kPaddedGroupSize;
        return float(reverseLow24(laineKarrasPermutation(groups_[group].reversed[j], groups_[group].seed[j]))) * 0x1p-24f;
      }
      return float(reverseLow24(paddedReversedBits(pixelKey_, paddedGroupIndex(pixelKey_, sampleInPixel_, group), dimension))) *
             0x1p-24f;
    }
    if (fast_ && unsigned(dimension) < unsigned(kSobolByteTableDimensions)) {
      const uint32_t reversed = kSobolReversedByteTables[dimension][0][lowByte_] ^ highBytesXor_[dimension];
      return scrambledReversedToUnitFloat(reversed, seeds_[dimension]);
    }
    return sampler_.getAt(index_, dimension);
  }
  // Where the sample lies on the film (Sampler::filmPosition of the sample index).
  FilmPosition filmPosition() const { return film_; }
  // The sequence point's index (the sample index itself without a pixel grid).
  uint64_t index() const { return index_; }
  // A uniform [0,1) number independent of every dimension (a hash of seed, index and
  // `stream`), for choices whose stratification would not reduce any error.
  float independent(uint64_t stream) const {
    return bitsToUnitFloat(uint32_t(hashWords(sampler_.seed(), index_, stream) >> 32));
  }

 private:
  // Padded dimensions (padded_sobol.h): each group's shuffled index computed once, on first use.
  [[gnu::noinline]] void fillGroup(int group) const {
    paddedGroup(pixelKey_, sampleInPixel_, group, groups_[group]);
    groupsKnown_ |= 1u << group;
  }
  static constexpr int kCachedGroups = 32;

  const Sampler& sampler_;
  bool padded_ = false;
  uint64_t pixelKey_ = 0;
  uint32_t sampleInPixel_ = 0;
  mutable uint32_t groupsKnown_ = 0;
  mutable PaddedGroup groups_[kCachedGroups];
  uint64_t index_;    // the point's index in the sequence
  FilmPosition film_;
  bool fast_;         // Sobol and index < 2^32
  uint32_t lowByte_;  // index & 0xff
  const uint32_t* seeds_;
  uint32_t highBytesXor_[kSobolByteTableDimensions];
};

const char* samplerName(SamplerKind kind);
std::optional<SamplerKind> parseSamplerKind(const std::string& name);

}  // namespace tex::sampling
