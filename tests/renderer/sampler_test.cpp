// Samplers: Sobol matches its definition, its leading two dimensions form (0,m,2)-nets before
// and after Owen scrambling, every dimension is stratified in 1-D, and both samplers are pure
// functions of (seed, index, dimension).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "renderer/sampling/pcg.h"
#include "renderer/sampling/sampler.h"
#include "renderer/sampling/sobol.h"

namespace tex::sampling {
namespace {

TEST(Sobol, UnscrambledPointsMatchTheDefinition) {
  // Dimension 0 is van der Corput; dimension 1 starts 0, 1/2, 3/4, 1/4, 5/8, 1/8 (index order).
  const double dim1[] = {0.0, 0.5, 0.75, 0.25, 0.625, 0.125};
  for (uint32_t i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(sobolBits(i, 1) * 0x1p-32, dim1[i]) << i;
  for (uint32_t i = 0; i < 1000; ++i) {
    uint32_t reversed = 0;
    for (int b = 0; b < 32; ++b) reversed |= ((i >> b) & 1u) << (31 - b);
    EXPECT_EQ(sobolBits(i, 0), reversed);
  }
}

TEST(Sobol, OwenScrambleIsANestedPermutation) {
  // Points sharing their top k bits still share them after scrambling (prefix-preserving),
  // and scrambling is a bijection on 16-bit prefixes.
  for (uint32_t seed : {1u, 0xdeadbeefu}) {
    std::vector<uint8_t> seen(1 << 16, 0);
    for (uint32_t v = 0; v < (1u << 16); ++v) {
      const uint32_t s = owenScramble(v << 16, seed) >> 16;
      EXPECT_EQ(seen[s], 0);
      seen[s] = 1;
      EXPECT_EQ(owenScramble(v << 16, seed) >> 20, owenScramble((v << 16) | 0xffffu, seed) >> 20);
    }
  }
}

// Checks that points [first, first + 2^m) of dims (0, 1) put exactly one point in every
// elementary interval of area 2^-m, for every split m = a + b.
::testing::AssertionResult isZeroTwoNet(const Sampler& sampler, uint64_t first, int m) {
  const uint64_t n = uint64_t(1) << m;
  std::vector<uint32_t> xs(n), ys(n);
  for (uint64_t i = 0; i < n; ++i) {
    xs[i] = sampler.getBits(first + i, 0);
    ys[i] = sampler.getBits(first + i, 1);
  }
  std::vector<uint32_t> counts(n);
  for (int a = 0; a <= m; ++a) {
    const int b = m - a;
    std::fill(counts.begin(), counts.end(), 0);
    for (uint64_t i = 0; i < n; ++i) {
      const uint64_t cx = a == 0 ? 0 : xs[i] >> (32 - a), cy = b == 0 ? 0 : ys[i] >> (32 - b);
      counts[(cy << a) | cx]++;
    }
    for (uint64_t c = 0; c < n; ++c) {
      if (counts[c] != 1) {
        return ::testing::AssertionFailure() << "interval split " << a << "+" << b << " cell " << c << " holds "
                                             << counts[c] << " points (m=" << m << ", first=" << first << ")";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(Sobol, LeadingDimensionsAreZeroTwoNetsScrambledOrNot) {
  for (int m : {1, 4, 8, 12, 16}) {
    EXPECT_TRUE(isZeroTwoNet(Sampler(SamplerKind::Sobol, 0), 0, m));
    for (uint64_t seed : {1ull, 42ull, 0x123456789abcdefull}) {
      EXPECT_TRUE(isZeroTwoNet(Sampler(SamplerKind::Sobol, seed), 0, m));
      // Every aligned block of 2^m consecutive indices is a net too (a (0,2)-sequence).
      EXPECT_TRUE(isZeroTwoNet(Sampler(SamplerKind::Sobol, seed), uint64_t(7) << m, m));
    }
  }
  // Above 2^32 the index's high word selects a new scramble; still a net.
  EXPECT_TRUE(isZeroTwoNet(Sampler(SamplerKind::Sobol, 9), (uint64_t(3) << 32) + (uint64_t(5) << 12), 12));
  // The random baseline is not a net: this check can fail.
  EXPECT_FALSE(isZeroTwoNet(Sampler(SamplerKind::Random, 1), 0, 8));
}

TEST(Sobol, FirstTwoDimensionsWithoutMatricesMatchTheMatrices) {
  // The shift-and-xor form of dimensions 0 and 1 against the Joe-Kuo matrices, over dense
  // small indices, every single bit and pseudo-random words.
  auto check = [](uint32_t i) {
    uint32_t x = 0, y = 0;
    sobolFirstTwoReversed(i, x, y);
    ASSERT_EQ(x, reverseBits32(sobolBits(i, 0))) << i;
    ASSERT_EQ(y, reverseBits32(sobolBits(i, 1))) << i;
  };
  for (uint32_t i = 0; i < (1u << 16); ++i) check(i);
  for (int b = 0; b < 32; ++b) check(1u << b), check(~(1u << b));
  Pcg32 rng(7, 1);
  for (int k = 0; k < 100000; ++k) check(rng.nextBits());
}

TEST(Sobol, FilmPositionFastPathMatchesGenericDimensions) {
  const Sampler sampler(SamplerKind::Sobol, 77);
  for (uint64_t i : {0ull, 1ull, 255ull, 256ull, 65537ull, 0xfffffffeull, 0x100000003ull, 123456789012ull}) {
    const FilmPosition p = sampler.filmPosition(i);
    EXPECT_EQ(p.x, sampler.get(i, 0));
    EXPECT_EQ(p.y, sampler.get(i, 1));
  }
}

// get() reaches the scrambled Sobol bits by reversed tables and a 24-bit reversal: it must
// equal the definition (owenScramble of sobolBits, kept to a float's 24 bits) in every
// dimension range (byte tables, matrix loop, hashed fallback) and for indices past 2^32.
TEST(Sobol, GetMatchesTheScrambledDefinition) {
  const Sampler sampler(SamplerKind::Sobol, 31);
  Pcg32 rng(11, 3);
  for (int k = 0; k < 2000; ++k) {
    const uint64_t index = k < 1000 ? rng.nextBits() : (uint64_t(rng.nextBits() & 7u) << 32) | rng.nextBits();
    for (int d : {2, 3, 17, 63, 64, 65, 500, 1023, 1024, 2000}) {
      ASSERT_EQ(sampler.get(index, d), bitsToUnitFloat(sampler.getBits(index, d))) << index << " " << d;
      if (index >> 32 == 0 && d < kSobolDimensions) {
        ASSERT_EQ(sampler.getBits(index, d), owenScramble(sobolBits(uint32_t(index), d), sobolScrambleSeed(31, d, 0)));
      }
    }
  }
  for (uint32_t x : {0u, 1u, 0x800000u, 0xffffffu, 0x12345678u, 0xffffffffu}) EXPECT_EQ(reverseLow24(x), reverseBits32(x) >> 8);
}

TEST(Samplers, IndexSamplerGivesSamplerGetBitForBit) {
  // Per-index views interleaved in index orders that cross and revisit blocks of 256 indices
  // (the per-thread XOR of the high bytes is refreshed and reused), for both samplers, every
  // fast dimension and some past it, and indices past 2^32 (the general path).
  for (const SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Random}) {
    const Sampler sampler(kind, 17);
    std::mt19937_64 rng(5);
    std::vector<uint64_t> indices = {0, 1, 255, 256, 257, 65535, 65536, 0xffffffffull, 0x100000000ull, 0x1234567890ull};
    for (int i = 0; i < 2000; ++i) indices.push_back(rng() % (uint64_t(1) << (i % 2 ? 12 : 32)));
    for (const uint64_t index : indices) {
      const IndexSampler samples(sampler, index);
      for (int d = 0; d < kSobolByteTableDimensions + 8; ++d) {
        const float a = samples.get(d), b = sampler.get(index, d);
        ASSERT_EQ(std::bit_cast<uint32_t>(a), std::bit_cast<uint32_t>(b)) << "index " << index << " dimension " << d;
      }
    }
  }
}

// Dimensions 2 and up of a render's samples are padded per pixel (padded_sobol.h): the N samples
// of any pixel stratify every dimension (one in each 1/N of [0,1)) and the first two of every
// group of four (one in each elementary interval of a (0,m,2)-net), at any resolution, seed and
// depth. They had taken the film-wide points, whose per-pixel sets were rank-deficient at some
// sizes: at 1920 x 1080 and 4 spp all 4 samples of every pixel fell in one quarter of
// dimensions 7 and 10, and Sobol's MSE on a lit plane was up to 4.4x the random sampler's.
// IndexSampler still gives Sampler::get bit for bit.
TEST(Samplers, EveryPixelsSamplesAreStratifiedInEachPaddedDimensionAndPair) {
  struct Case {
    int width, height, spp;
  };
  for (const Case c : {Case{1920, 1080, 4}, Case{1024, 1024, 16}, Case{64, 64, 4}, Case{300, 200, 64}}) {
    PixelGrid grid;
    grid.width = grid.imageWidth = c.width;
    grid.height = grid.imageHeight = c.height;
    for (uint64_t seed : {2u, 3u, 7u}) {
      const Sampler sampler(SamplerKind::Sobol, seed, grid);
      const int m = std::countr_zero(unsigned(c.spp));
      const uint64_t pixels = uint64_t(c.width) * uint64_t(c.height);
      for (uint64_t pixel : {uint64_t(0), pixels / 3, pixels - 1}) {
        // Sample s of the pixel at position `pixel` of the enumeration order is index s W H + pixel.
        std::vector<std::vector<uint32_t>> bits(64);
        for (int s = 0; s < c.spp; ++s) {
          const uint64_t index = uint64_t(s) * pixels + pixel;
          const IndexSampler samples(sampler, index);
          for (int d = 2; d < 64; ++d) {
            bits[size_t(d)].push_back(sampler.getBits(index, d));
            ASSERT_EQ(std::bit_cast<uint32_t>(samples.get(d)), std::bit_cast<uint32_t>(sampler.get(index, d)));
          }
        }
        for (int d = 2; d < 64; ++d) {
          std::vector<int> strata(size_t(c.spp), 0);
          for (uint32_t b : bits[size_t(d)]) ++strata[b >> (32 - m)];
          for (int k = 0; k < c.spp; ++k)
            ASSERT_EQ(strata[size_t(k)], 1) << c.width << "x" << c.height << " spp " << c.spp << " seed " << seed << " dimension " << d;
          if (d % 4 != 0) continue;
          for (int xBits = 0; xBits <= m; ++xBits) {  // elementary intervals 2^-xBits x 2^-(m - xBits)
            std::vector<int> cells(size_t(c.spp), 0);
            for (int s = 0; s < c.spp; ++s) {
              const uint32_t x = xBits ? bits[size_t(d)][size_t(s)] >> (32 - xBits) : 0;
              const uint32_t y = xBits < m ? bits[size_t(d + 1)][size_t(s)] >> (32 - (m - xBits)) : 0;
              ++cells[size_t((x << (m - xBits)) | y)];
            }
            for (int k = 0; k < c.spp; ++k)
              ASSERT_EQ(cells[size_t(k)], 1) << c.width << "x" << c.height << " dimensions " << d << "," << d + 1 << " split " << xBits;
          }
        }
      }
    }
  }
}

TEST(Sobol, EveryDimensionIsStratifiedInOneDimension) {
  const int m = 10;
  const Sampler sampler(SamplerKind::Sobol, 5);
  std::vector<uint8_t> hit(1 << m);
  for (int d = 0; d < kSobolDimensions; ++d) {
    std::fill(hit.begin(), hit.end(), 0);
    for (uint32_t i = 0; i < (1u << m); ++i) hit[sampler.getBits(i, d) >> (32 - m)]++;
    for (uint8_t h : hit) ASSERT_EQ(h, 1) << "dimension " << d;
  }
}

TEST(Samplers, SameIndexGivesSameValuesWhateverCameBefore) {
  for (SamplerKind kind : {SamplerKind::Sobol, SamplerKind::Random}) {
    const Sampler sampler(kind, 1234);
    const int dims = 40;
    const uint64_t n = 2000;
    std::vector<float> forward(n * dims);
    for (uint64_t i = 0; i < n; ++i)
      for (int d = 0; d < dims; ++d) forward[i * dims + d] = sampler.get(i, d);
    // Shuffled order, interleaved with unrelated queries, and from another thread.
    std::vector<uint64_t> order(n * dims);
    for (uint64_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
    const Sampler other(kind, 99);
    std::thread worker([&] {
      for (uint64_t k : order) {
        (void)other.get(k % 977, int(k % 13));
        ASSERT_EQ(sampler.get(k / dims, int(k % dims)), forward[k]);
      }
    });
    worker.join();
    // Values are in [0,1) and the seed matters.
    for (float v : forward) ASSERT_TRUE(v >= 0.0f && v < 1.0f);
    EXPECT_NE(Sampler(kind, 1).get(3, 3), Sampler(kind, 2).get(3, 3));
  }
}

TEST(Pcg, AdvanceEqualsSteppingAndUniformityChiSquare) {
  Pcg32 a(42, 54), b(42, 54);
  for (int i = 0; i < 1000; ++i) a.nextBits();
  b.advance(1000);
  EXPECT_EQ(a.nextBits(), b.nextBits());
  // Chi-square of the random sampler's dims (5, 6) on a 16x16 grid: 255 degrees of freedom,
  // the 0.999 quantile is 330.5.
  const Sampler sampler(SamplerKind::Random, 3);
  const int n = 256 * 400;
  std::vector<int> counts(256, 0);
  for (int i = 0; i < n; ++i) counts[int(sampler.get(i, 5) * 16) * 16 + int(sampler.get(i, 6) * 16)]++;
  double chi2 = 0;
  for (int c : counts) chi2 += (c - 400.0) * (c - 400.0) / 400.0;
  EXPECT_LT(chi2, 330.5);
}

// A render's pixel grid (pixel_grid.h): every pixel gets exactly its samples at any
// resolution, each pixel's s-th sample is the point of the film-wide sequence's block s that
// lies in its cell (so its film offsets are stratified), square power-of-two films get the
// film-wide positions bit for bit, and a crop window's pixels get the full image's points.
TEST(PixelGrid, EveryPixelGetsItsSamplesFromItsOwnCellOfEachBlock) {
  struct Case {
    int width, height;
  };
  for (const Case c : {Case{100, 37}, Case{1, 1}, Case{3, 300}, Case{64, 64}}) {
    PixelGrid grid;
    grid.width = grid.imageWidth = c.width;
    grid.height = grid.imageHeight = c.height;
    const Sampler plain(SamplerKind::Sobol, 9);
    const Sampler gridded(SamplerKind::Sobol, 9, grid);
    const int spp = 16;
    const int cells = int(std::bit_ceil(unsigned(std::max(c.width, c.height))));
    std::vector<std::vector<FilmPosition>> perPixel(size_t(c.width) * size_t(c.height));
    for (uint64_t i = 0; i < uint64_t(c.width) * uint64_t(c.height) * spp; ++i) {
      const IndexSampler samples(gridded, i);
      const FilmPosition f = samples.filmPosition();
      ASSERT_EQ(f.x, gridded.filmPosition(i).x);
      ASSERT_EQ(f.y, gridded.filmPosition(i).y);
      ASSERT_EQ(samples.get(5), gridded.get(i, 5));
      const int px = int(f.x * float(c.width)), py = int(f.y * float(c.height));
      ASSERT_TRUE(px >= 0 && px < c.width && py >= 0 && py < c.height);
      perPixel[size_t(py) * size_t(c.width) + size_t(px)].push_back(f);
      // The Sobol point itself lies in the pixel's cell of 2^r x 2^r, in block i / (W H).
      const FilmPosition point = plain.filmPosition(samples.index());
      ASSERT_EQ(int(point.x * float(cells)), px) << c.width << "x" << c.height << " index " << i;
      ASSERT_EQ(int(point.y * float(cells)), py) << c.width << "x" << c.height << " index " << i;
      ASSERT_EQ(samples.index() >> (2 * std::bit_width(unsigned(cells) - 1)), i / (uint64_t(c.width) * c.height));
      if (c.width == c.height && std::has_single_bit(unsigned(c.width))) {
        ASSERT_EQ(f.x, point.x);
        ASSERT_EQ(f.y, point.y);
      }
    }
    for (const auto& samples : perPixel) {
      ASSERT_EQ(samples.size(), size_t(spp)) << c.width << "x" << c.height;
      // The 16 offsets within the pixel are a (0,4,2)-net: one per 1/4 x 1/4 stratum.
      std::vector<int> strata(16, 0);
      for (const FilmPosition& f : samples) {
        const float ox = f.x * float(c.width) - std::floor(f.x * float(c.width));
        const float oy = f.y * float(c.height) - std::floor(f.y * float(c.height));
        ++strata[size_t(int(ox * 4) * 4 + int(oy * 4))];
      }
      EXPECT_EQ(*std::max_element(strata.begin(), strata.end()), 1) << c.width << "x" << c.height;
    }
  }
  // Wide films whose sizes are not powers of two: a sample at the pixel's left edge had been
  // placed by the rounded 1/W just below x / W, and binned by the film into the pixel to the
  // left (a 40000x3 render at 4 spp had pixels of 2 to 6 samples).
  for (const Case c : {Case{40000, 3}, Case{5000, 5}, Case{1920, 8}}) {
    PixelGrid grid;
    grid.width = grid.imageWidth = c.width;
    grid.height = grid.imageHeight = c.height;
    const Sampler gridded(SamplerKind::Sobol, 9, grid);
    std::vector<int> counts(size_t(c.width) * size_t(c.height), 0);
    for (uint64_t i = 0; i < uint64_t(c.width) * uint64_t(c.height) * 4; ++i) {
      const FilmPosition f = IndexSampler(gridded, i).filmPosition();
      const int px = std::min(int(f.x * float(c.width)), c.width - 1), py = std::min(int(f.y * float(c.height)), c.height - 1);
      ++counts[size_t(py) * size_t(c.width) + size_t(px)];
    }
    EXPECT_EQ(*std::min_element(counts.begin(), counts.end()), 4) << c.width << "x" << c.height;
    EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), 4) << c.width << "x" << c.height;
  }
  // Past 2^32 Sobol indices (large images at high counts) a sample still lands in its pixel.
  {
    PixelGrid grid;
    grid.width = grid.imageWidth = 64;
    grid.height = grid.imageHeight = 48;
    const Sampler gridded(SamplerKind::Sobol, 3, grid);
    for (uint64_t p : {uint64_t(0), uint64_t(5), uint64_t(3071)}) {
      const FilmPosition low = gridded.filmPosition(p);
      const uint64_t far = p + uint64_t(64 * 48) * (uint64_t(1) << 21);  // block 2^21: index past 2^33
      const IndexSampler samples(gridded, far);
      ASSERT_GT(samples.index(), uint64_t(1) << 32);
      const FilmPosition high = samples.filmPosition();
      EXPECT_EQ(int(low.x * 64), int(high.x * 64)) << p;
      EXPECT_EQ(int(low.y * 48), int(high.y * 48)) << p;
      EXPECT_GE(samples.get(7), 0.0f);
      EXPECT_LT(samples.get(7), 1.0f);
    }
  }
  // A crop window's pixels draw the full image's points.
  PixelGrid full, crop;
  full.width = full.imageWidth = crop.imageWidth = 90;
  full.height = full.imageHeight = crop.imageHeight = 70;
  crop.width = 20, crop.height = 10, crop.originX = 33, crop.originY = 41;
  const Sampler whole(SamplerKind::Sobol, 4, full), window(SamplerKind::Sobol, 4, crop);
  std::vector<uint64_t> fullPoints, windowPoints;
  for (uint64_t i = 0; i < 90 * 70 * 4; ++i) {
    const FilmPosition f = whole.filmPosition(i);
    const int px = int(f.x * 90), py = int(f.y * 70);
    if (px >= 33 && px < 53 && py >= 41 && py < 51) fullPoints.push_back(IndexSampler(whole, i).index());
  }
  for (uint64_t i = 0; i < 20 * 10 * 4; ++i) windowPoints.push_back(IndexSampler(window, i).index());
  std::sort(fullPoints.begin(), fullPoints.end());
  std::sort(windowPoints.begin(), windowPoints.end());
  EXPECT_EQ(fullPoints, windowPoints);
}

}  // namespace
}  // namespace tex::sampling

namespace tex::sampling {
namespace {

// The padded groups of one pixel are independent of each other: the halves of dimension j of
// group g and of group h (e.g. the light choice at two bounces) pair up at random, so that over
// a pixel's N samples the fraction A on which [x_g < 1/2] == [x_h < 1/2] is about 1/2. A
// uniformly random pairing gives E (A - 1/2)^2 = 1 / (4 N); a shuffle that keeps every
// power-of-two prefix of the samples stratified (a nested one) pairs them two at a time (the
// two samples of a stratum pair land in opposite halves in both groups, so they agree or
// disagree together): about 1 / (2 N), measured 1.9-2.1 / (4 N). When every group took Sobol dimensions 0-3 of the sample
// number XOR a constant, x_g and x_h were nested scrambles of one value: A was 0 or 1 in every
// pixel (the two bounces' choices moved together), which multiplied the error of multi-bounce
// renders (a many-light scene's pixels differed between seeds by 2.3x what their variance
// predicted).
TEST(Samplers, PaddedGroupsOfAPixelAreIndependent) {
  PixelGrid grid;
  grid.width = grid.imageWidth = 64;
  grid.height = grid.imageHeight = 64;
  const uint64_t pixels = 64 * 64;
  for (const int spp : {16, 64}) {
    const Sampler sampler(SamplerKind::Sobol, 5, grid);
    for (const int j : {0, 1, 2, 3})
      for (const auto& [g, h] : {std::pair{2, 3}, std::pair{2, 4}, std::pair{3, 10}}) {
        double meanSquare = 0;
        constexpr int kPixels = 512;
        for (uint64_t pixel = 0; pixel < kPixels; ++pixel) {
          int agree = 0;
          for (int s = 0; s < spp; ++s) {
            const IndexSampler samples(sampler, uint64_t(s) * pixels + pixel * 7);
            agree += (samples.get(4 * g + j) < 0.5f) == (samples.get(4 * h + j) < 0.5f);
          }
          const double a = double(agree) / spp - 0.5;
          meanSquare += a * a / kPixels;
        }
        // 1 / (2 N), with a standard error of about sqrt(2 / kPixels) of itself; linked groups
        // give 1/4.
        const double expected = 1.0 / (2.0 * spp);
        EXPECT_LT(meanSquare, 1.4 * expected) << meanSquare << " vs " << expected << ": spp " << spp << ", dimension " << j << " of groups " << g << " and " << h;
        EXPECT_GT(meanSquare, 0.6 * expected) << "spp " << spp << ", dimension " << j << " of groups " << g << " and " << h;
      }
  }
}

}  // namespace
}  // namespace tex::sampling
