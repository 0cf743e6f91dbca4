// Sample indices of a render mapped onto its pixels, so that every pixel gets exactly its share
// of samples whatever the resolution. (A film-wide Sobol sequence spread over the image covers
// pixels evenly only when both sides are powers of two: at 100x100 and 1 spp a quarter of the
// pixels had no sample and the image developed 25 % dark.)
//
// The image is padded to a square of 2^r x 2^r cells (2^r >= its longer side) and the global
// Owen-scrambled Sobol sequence is used as before: its first two dimensions are a (0,2)-sequence,
// so every aligned block of 2^(2r) points puts one point in each cell. Sample s of pixel (x, y)
// is the point of block s that lands in cell (x, y): Sobol index c(x, y) + s 2^(2r), with c found
// by inverting the first two dimensions' scrambles and generator matrices (as pbrt-v3's
// SobolSampler does for its unscrambled points). Sample index i of a render is the
// floor(i / (W H))-th sample of the (i mod (W H))-th pixel in the order of their block-0 points
// (see pixelOrder_), so every prefix of the index range covers the film evenly (time limits,
// Ctrl-C). At square power-of-two resolutions the points are exactly
// those the film-wide sequence gave, only enumerated pixel by pixel; elsewhere the cells outside
// the image are skipped, not wasted. Pixel coordinates are the image's, so a crop window draws
// the same samples for its pixels as the full render does.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "renderer/sampling/sobol.h"

namespace tex::sampling {

struct PixelGrid {
  int width = 0, height = 0;            // the film: the whole image or a crop window of it
  int originX = 0, originY = 0;         // the film's first pixel in the image
  int imageWidth = 0, imageHeight = 0;  // the image
  bool valid() const {
    return width > 0 && height > 0 && imageWidth > 0 && imageHeight > 0 && imageWidth <= 65536 && imageHeight <= 65536;
  }
};

// Where a sample index goes: its film pixel and the Sobol point's index.
struct PixelSample {
  int x = 0, y = 0;
  uint64_t sobolIndex = 0;
  uint64_t sampleInPixel = 0;  // s: this is the pixel's s-th sample
};

class PixelSampleMap {
 public:
  PixelSampleMap() = default;
  // filmScrambleSeeds: the Owen scramble seeds of Sobol dimensions 0 and 1 (the sampler's).
  PixelSampleMap(const PixelGrid& grid, const uint32_t filmScrambleSeeds[2]);
  PixelSample map(uint64_t index) const {
    PixelSample out;
    // Kernels run consecutive indices on a thread: step from the thread's previous index
    // instead of dividing (the division showed in the profile).
    struct Last {
      uint64_t map = 0;  // id_ (not the address: another map may take this one's place)
      uint64_t index = 0, p = 0, s = 0;
    };
    thread_local Last last;
    uint64_t p, s;
    if (last.map == id_ && index == last.index + 1) {
      p = last.p + 1;
      s = last.s;
      if (p == pixels_) p = 0, ++s;
    } else {
      p = index % pixels_;
      s = index / pixels_;
    }
    last = {id_, index, p, s};
    const uint32_t pixel = pixelOrder_[size_t(p)];
    out.x = int(pixel % uint32_t(grid_.width));
    out.y = int(pixel / uint32_t(grid_.width));
    // Block s's index bits shift dimension 1 (not dimension 0's top bits) by their own share,
    // which moves the cell's index in block s by M^-1 of it in bits r..2r-1.
    const uint64_t block = s << (2 * cellBits_);
    uint32_t blockPart = 0;
    if (block >> 32 == 0) {
      uint32_t unused = 0;
      sobolFirstTwoReversed(uint32_t(block), unused, blockPart);
      blockPart &= cellMask_;
    }
    out.sobolIndex = (uint64_t(firstBlockIndex_[size_t(p)]) ^ (uint64_t(applyHighInverse(blockPart)) << cellBits_)) + block;
    out.sampleInPixel = s;
    return out;
  }
  const PixelGrid& grid() const { return grid_; }
  float inverseWidth() const { return inverseWidth_; }
  float inverseHeight() const { return inverseHeight_; }
  // Whether (x + offset) * inverse is exact for every pixel x and in-cell offset (power-of-two
  // sizes): then a position always bins into its own pixel and needs no check.
  bool widthExact() const { return widthExact_; }
  bool heightExact() const { return heightExact_; }
  int cellBits() const { return cellBits_; }  // r

 private:
  uint32_t applyHighInverse(uint32_t v) const {
    return highInverseBytes_[0][v & 0xffu] ^ highInverseBytes_[1][(v >> 8) & 0xffu];
  }
  PixelGrid grid_;
  uint64_t id_ = 0;  // unique per constructed map (copies share it: they map alike)
  uint64_t pixels_ = 1;
  float inverseWidth_ = 1, inverseHeight_ = 1;
  bool widthExact_ = true, heightExact_ = true;
  int cellBits_ = 0;
  uint32_t cellMask_ = 0;  // 2^r - 1
  // The film's pixels (y * width + x) in the order of their points' indices in block 0, and
  // those indices. Consecutive sample indices then take nearby Sobol indices, which share the
  // sampler's per-block tables (IndexSampler); in pixel order they missed them, 7 % slower.
  std::vector<uint32_t> pixelOrder_, firstBlockIndex_;
  // The inverse of the map from the index's bits r..2r-1 to dimension 1's reversed low r bits,
  // by bytes.
  uint32_t highInverseBytes_[2][256] = {};
};

}  // namespace tex::sampling
