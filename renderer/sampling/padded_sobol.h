// Dimensions 2 and up of a render's samples with the Sobol sampler and a pixel grid: padded per
// pixel (Burley 2020, "Practical Hash-based Owen Scrambling", section 4; pbrt-v4's padded and
// Z-order Sobol samplers do the same). Dimensions come in groups of four, d = 4 g + j: sample s
// of a pixel takes Sobol dimension j of the index s shuffled by a nested scramble seeded by
// (pixel, g) (a random aligned block of Sobol points, in a random order), Owen-scrambled by
// (pixel, d). So in every group the N samples of a pixel stratify each dimension in 1D and the
// group's first two dimensions as a (0,m,2)-net (Sobol's first two dimensions; the other pairs
// of dimensions 0-3 are (t,m,2)-nets with t > 0), independently randomised per pixel, at any
// depth (every group uses Sobol dimensions 0-3 only).
//
// Why: until round 16 these dimensions took the film-wide point of the sample (pixel_grid.h)
// with one scramble per dimension for the whole image. A pixel's samples were then one fixed
// linear point set plus a per-pixel shift, rank-deficient in the top bits at some resolutions
// and counts (all 4 samples of every pixel of a 1920 x 1080 image in one quarter of dimensions
// 7 and 10), and whether that cluster helped or hurt was decided once per seed: Sobol's MSE on
// a lit plane was 0.2-0.5x the random sampler's for some seeds and 4-4.4x for others.
// Kernels should put 2D pairs first in a group (path_tracer.h lays its dimensions out so).
#pragma once
#include <cstdint>

#include "renderer/sampling/hash.h"
#include "renderer/sampling/sobol.h"

namespace tex::sampling {

inline constexpr int kPaddedGroupSize = 4;

// The key of a pixel of the image (not of a crop window: windows draw the full render's samples).
inline uint64_t paddedPixelKey(uint64_t seed, int imageX, int imageY) {
  return hashWords(seed, (uint64_t(uint32_t(imageY)) << 32) | uint32_t(imageX), 0x5041444445445058ull);
}

// Sample s's index into the Sobol sequence for dimension group g of the pixel: s shuffled by a
// nested uniform scramble of its bits seeded by (pixel, group) (Burley 2020, section 4: each
// bit flipped by a hash of the bits above it), so that the first 2^k samples of the pixel take
// an aligned block of 2^k Sobol points (a (0,m,2)-net in dimensions 0 and 1) in a random order,
// a different order for every group. Until round 17 the shuffle was s XOR a random word: a
// linear one, under which dimension j of every group was a nested scramble of one value (the
// j-th Sobol coordinate of s), so the groups moved together: in every pixel the samples with
// [x < 1/2] in dimension j of one group were exactly those with it (or without it) in another
// (Samplers.PaddedGroupsOfAPixelAreIndependent). The pixel key is already a 64-bit hash: one
// 32-bit mix per group and per dimension suffices (a path reads about 40 dimensions; two 64-bit
// mixes each had cost 9 % of a Cornell render).
inline uint32_t paddedGroupIndex(uint64_t pixelKey, uint32_t sampleInPixel, int group) {
  return owenScramble(sampleInPixel, lowbias32(uint32_t(pixelKey >> 32) ^ (uint32_t(group) * 0x9e3779b9u)));
}

inline uint32_t paddedScrambleSeed(uint64_t pixelKey, int dimension) {
  return lowbias32(uint32_t(pixelKey) ^ (uint32_t(dimension) * 0x9e3779b9u));
}

// Coordinate `dimension` of the group's shuffled index, Owen-scrambled, still bit-reversed.
inline uint32_t paddedReversedBits(uint64_t pixelKey, uint32_t groupIndex, int dimension) {
  // Sobol dimensions 0 and 1 in closed form (no table loads: the 2D pairs sit there), 2 and 3
  // from the byte tables.
  const int j = dimension % kPaddedGroupSize;
  uint32_t reversed = groupIndex;
  if (j == 1) {
    uint32_t unused = 0;
    sobolFirstTwoReversed(groupIndex, unused, reversed);
  } else if (j > 1) {
    reversed = sobolReversedBitsFast(groupIndex, j);
  }
  return laineKarrasPermutation(reversed, paddedScrambleSeed(pixelKey, dimension));
}

// A group's four coordinates before their last step, computed together on the group's first
// use (what IndexSampler keeps): the reversed Sobol bits and the four scramble seeds (hashed as
// one vector), so that each coordinate then costs one Laine-Karras permutation.
struct PaddedGroup {
  uint32_t reversed[kPaddedGroupSize];
  uint32_t seed[kPaddedGroupSize];
};
inline void paddedGroup(uint64_t pixelKey, uint32_t sampleInPixel, int group, PaddedGroup& out) {
  const uint32_t index = paddedGroupIndex(pixelKey, sampleInPixel, group);
  out.reversed[0] = index;
  sobolFirstTwoReversed(index, out.reversed[0], out.reversed[1]);
  out.reversed[2] = sobolReversedBitsFast(index, 2);
  out.reversed[3] = sobolReversedBitsFast(index, 3);
  typedef uint32_t U4 __attribute__((vector_size(16)));
  const uint32_t d0 = uint32_t(group * kPaddedGroupSize);
  const U4 dims = {d0, d0 + 1, d0 + 2, d0 + 3};
  const U4 seeds = lowbias32((U4{} + uint32_t(pixelKey)) ^ (dims * 0x9e3779b9u));
  for (int j = 0; j < kPaddedGroupSize; ++j) out.seed[j] = seeds[j];
}

// ... as 32 fixed-point bits.
inline uint32_t paddedBits(uint64_t pixelKey, uint32_t groupIndex, int dimension) {
  return reverseBits32(paddedReversedBits(pixelKey, groupIndex, dimension));
}

}  // namespace tex::sampling
