#include "renderer/sampling/pixel_grid.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <stdexcept>

#include "renderer/sampling/sobol.h"

namespace tex::sampling {

namespace {

int ceilLog2(uint64_t n) {
  int bits = 0;
  while (bits < 63 && (uint64_t(1) << bits) < n) ++bits;
  return bits;
}

uint32_t reverseLowBits(uint32_t v, int bits) { return bits == 0 ? 0 : reverseBits32(v) >> (32 - bits); }

// Dimension 1's reversed bits of index c (sobolFirstTwoReversed's superset transform).
uint32_t dimensionOneReversed(uint32_t c) {
  uint32_t x = 0, y = 0;
  sobolFirstTwoReversed(c, x, y);
  return y;
}

// inverse[L(v)] = v for v < 2^bits, L(v) = the low `bits` bits of laineKarrasPermutation(v,
// seed): a bijection of those bits, since each output bit depends only on lower input bits.
std::vector<uint32_t> invertLowBits(int bits, uint32_t seed) {
  const uint32_t n = uint32_t(1) << bits, mask = n - 1;
  std::vector<uint32_t> inverse(n);
  for (uint32_t v = 0; v < n; ++v) inverse[laineKarrasPermutation(v, seed) & mask] = v;
  return inverse;
}

}  // namespace

PixelSampleMap::PixelSampleMap(const PixelGrid& grid, const uint32_t filmScrambleSeeds[2]) : grid_(grid) {
  if (!grid.valid()) throw std::invalid_argument("PixelSampleMap: invalid pixel grid");
  static std::atomic<uint64_t> nextId{1};
  id_ = nextId.fetch_add(1, std::memory_order_relaxed);
  pixels_ = uint64_t(grid.width) * uint64_t(grid.height);
  inverseWidth_ = 1.0f / float(grid.width);
  inverseHeight_ = 1.0f / float(grid.height);
  widthExact_ = (grid.width & (grid.width - 1)) == 0;
  heightExact_ = (grid.height & (grid.height - 1)) == 0;
  const int r = ceilLog2(uint64_t(std::max(grid.imageWidth, grid.imageHeight)));
  cellBits_ = r;
  const uint32_t mask = r == 0 ? 0u : (uint32_t(1) << r) - 1;  // r <= 16
  cellMask_ = mask;
  // A point's scrambled dimension-0 value has top r bits reverse_r(low r bits of
  // laineKarras(c, seed0)) (dimension 0 reversed is the index itself); so cell column X needs
  // c's low r bits = inverse0[reverse_r(X)].
  const std::vector<uint32_t> inverse0 = invertLowBits(r, filmScrambleSeeds[0]);
  const std::vector<uint32_t> inverse1 = invertLowBits(r, filmScrambleSeeds[1]);
  std::vector<uint32_t> columnLow(size_t(grid.width)), columnPart(size_t(grid.width));
  for (int x = 0; x < grid.width; ++x) {
    const uint32_t low = inverse0[reverseLowBits(uint32_t(grid.originX + x), r)];
    columnLow[size_t(x)] = low;
    columnPart[size_t(x)] = dimensionOneReversed(low) & mask;
  }
  // Dimension 1 likewise needs its reversed low r bits = inverse1[reverse_r(Y)]; they are
  // linear in c: (part of the low bits) xor M (bits r..2r-1 of c).
  std::vector<uint32_t> rowTarget(size_t(grid.height));
  for (int y = 0; y < grid.height; ++y) rowTarget[size_t(y)] = inverse1[reverseLowBits(uint32_t(grid.originY + y), r)];
  // M's columns, then its inverse by Gauss-Jordan elimination over GF(2). M is invertible
  // because the first two Sobol dimensions form a (0,2)-sequence (each cell gets one point of
  // every block of 2^(2r)).
  std::array<uint32_t, 32> rows{}, inverseRows{};  // row k: bit j = M[k][j]
  for (int j = 0; j < r; ++j) {
    const uint32_t column = dimensionOneReversed(uint32_t(1) << (r + j)) & mask;
    for (int k = 0; k < r; ++k)
      if (column >> k & 1u) rows[size_t(k)] |= uint32_t(1) << j;
  }
  for (int k = 0; k < r; ++k) inverseRows[size_t(k)] = uint32_t(1) << k;
  for (int col = 0; col < r; ++col) {
    int pivot = col;
    while (pivot < r && !(rows[size_t(pivot)] >> col & 1u)) ++pivot;
    if (pivot == r) throw std::logic_error("PixelSampleMap: singular Sobol block (not a (0,2)-sequence?)");
    std::swap(rows[size_t(pivot)], rows[size_t(col)]);
    std::swap(inverseRows[size_t(pivot)], inverseRows[size_t(col)]);
    for (int k = 0; k < r; ++k)
      if (k != col && (rows[size_t(k)] >> col & 1u)) {
        rows[size_t(k)] ^= rows[size_t(col)];
        inverseRows[size_t(k)] ^= inverseRows[size_t(col)];
      }
  }
  // inverseRows[k] bit j: entry (k, j) of M^-1; apply as XOR of the columns selected by v's bits,
  // tabulated per byte of v.
  for (int b = 0; b < 2; ++b)
    for (uint32_t v = 0; v < 256; ++v) {
      uint32_t out = 0;
      for (int bit = 0; bit < 8; ++bit) {
        const int j = 8 * b + bit;
        if (j >= r || !(v >> bit & 1u)) continue;
        for (int k = 0; k < r; ++k)  // XOR in column j of M^-1
          if (inverseRows[size_t(k)] >> j & 1u) out ^= uint32_t(1) << k;
      }
      highInverseBytes_[b][v] = out;
    }
  // Every film pixel's index in block 0, in increasing order.
  std::vector<std::pair<uint32_t, uint32_t>> byIndex;
  byIndex.reserve(size_t(pixels_));
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const uint32_t high = applyHighInverse(rowTarget[size_t(y)] ^ columnPart[size_t(x)]);
      byIndex.emplace_back(columnLow[size_t(x)] | (high << r), uint32_t(y) * uint32_t(grid.width) + uint32_t(x));
    }
  std::sort(byIndex.begin(), byIndex.end());
  pixelOrder_.resize(byIndex.size());
  firstBlockIndex_.resize(byIndex.size());
  for (size_t i = 0; i < byIndex.size(); ++i) {
    firstBlockIndex_[i] = byIndex[i].first;
    pixelOrder_[i] = byIndex[i].second;
  }
}

}  // namespace tex::sampling
