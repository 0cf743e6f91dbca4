#include "renderer/film/film.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "renderer/color/cie_tables.h"
#include "renderer/color/spectral_to_rgb.h"

namespace tex {

namespace {

constexpr double kFixedScale = 16777216.0;  // 2^24 units per 1.0
constexpr double kFixedLimit = 4.0e18;      // per-record clamp, keeps a single add from wrapping

// Round to nearest fixed-point units; NaN becomes 0 and huge values saturate (branch-free).
inline int64_t toFixed(double x) {
  double scaled = x * kFixedScale;
  scaled = scaled == scaled ? scaled : 0.0;
  scaled = std::min(std::max(scaled, -kFixedLimit), kFixedLimit);
#if defined(__SSE2__)
  return _mm_cvtsd_si64(_mm_set_sd(scaled));  // rounds to nearest (the default MXCSR mode)
#else
  return std::llrint(scaled);
#endif
}
inline double fromFixed(int64_t x) { return double(x) / kFixedScale; }

// A pixel's running sums hold at most 2^63 units (5.5e11 in value; its squares' sums reach that
// first, at about 9e4 per sample over 64 samples): a sum that would pass it stays at the limit
// instead of wrapping to the other sign, and develop() reports the pixel. Sticky: a saturated
// sum no longer moves, since what it lost cannot be recovered.
constexpr int64_t kSumMax = INT64_MAX, kSumMin = INT64_MIN;
inline void addSaturating(int64_t& sum, int64_t v) {
  int64_t r;
  if (__builtin_expect(__builtin_add_overflow(sum, v, &r) || sum == kSumMax || sum == kSumMin, 0))
    r = sum == kSumMax || sum == kSumMin ? sum : (v > 0 ? kSumMax : kSumMin);
  sum = r;
}
inline bool isSaturated(int64_t sum) { return sum == kSumMax || sum == kSumMin; }

// Adds toFixed(v[k]) to s[k] for k = 0..3. The SSE2 path converts two values per instruction
// with the 1.5 * 2^52 trick, which rounds to nearest even exactly like cvtsd2si (and toFixed)
// for |scaled| < 2^51; anything larger (or NaN) takes the scalar toFixed, so the integers added
// are the same as toFixed's in every case.
inline void addFixed4(int64_t* s, double v0, double v1, double v2, double v3) {
#if defined(__SSE2__)
  const __m128d scale = _mm_set1_pd(kFixedScale);
  const __m128d lo = _mm_mul_pd(_mm_set_pd(v1, v0), scale), hi = _mm_mul_pd(_mm_set_pd(v3, v2), scale);
  const __m128d limit = _mm_set1_pd(0x1p51), absMask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffll));
  // Ordered-and-small in all four lanes (a NaN compares false, so it takes the slow path).
  const int small = _mm_movemask_pd(_mm_cmplt_pd(_mm_and_pd(lo, absMask), limit)) &
                    _mm_movemask_pd(_mm_cmplt_pd(_mm_and_pd(hi, absMask), limit));
  if (__builtin_expect(small == 3, 1)) {
    const __m128d magic = _mm_set1_pd(0x1.8p52);
    const __m128i magicBits = _mm_castpd_si128(magic);
    const __m128i fixedLo = _mm_sub_epi64(_mm_castpd_si128(_mm_add_pd(lo, magic)), magicBits);
    const __m128i fixedHi = _mm_sub_epi64(_mm_castpd_si128(_mm_add_pd(hi, magic)), magicBits);
    // |fixed| < 2^51, so a sum can only overflow (or be saturated) if it is outside
    // [-2^62, 2^62): bits 63 and 62 differ. Otherwise add in the vector registers.
    __m128i* p = reinterpret_cast<__m128i*>(s);
    const __m128i sumLo = _mm_loadu_si128(p), sumHi = _mm_loadu_si128(p + 1);
    const __m128i topBitsDiffer = _mm_or_si128(_mm_xor_si128(sumLo, _mm_slli_epi64(sumLo, 1)),
                                               _mm_xor_si128(sumHi, _mm_slli_epi64(sumHi, 1)));
    if (__builtin_expect(_mm_movemask_pd(_mm_castsi128_pd(topBitsDiffer)) == 0, 1)) {
      _mm_storeu_si128(p, _mm_add_epi64(sumLo, fixedLo));
      _mm_storeu_si128(p + 1, _mm_add_epi64(sumHi, fixedHi));
      return;
    }
    alignas(16) int64_t fixed[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(fixed), fixedLo);
    _mm_store_si128(reinterpret_cast<__m128i*>(fixed + 2), fixedHi);
    for (int k = 0; k < 4; ++k) addSaturating(s[k], fixed[k]);
    return;
  }
#endif
  addSaturating(s[0], toFixed(v0)), addSaturating(s[1], toFixed(v1));
  addSaturating(s[2], toFixed(v2)), addSaturating(s[3], toFixed(v3));
}

// Layout of one pixel's sums. Colour films: a, a^2, a c (3), a^2 c^2 (3) and, with a filter
// other than box, a^2 c (3) and an unused sum (so that the three convert as one SIMD group:
// the Gaussian-filtered Cornell box renders 3.4 % slower than without them, 5.9 % with three
// scalar conversions); then the spectral bins. A box film's a is the record's weight,
// which the renderer and the demo set to 1: then sum a^2 c = (sum a^2 / sum a) sum a c exactly,
// so it is not stored and a pixel stays one cache line. Scalar films: a, a^2, a c, a^2 c^2
// [, a^2 c].
enum : int { kSumA = 0, kSumA2 = 1, kSumAC = 2, kSumA2C2 = 5, kSumA2C = 8 };
enum : int { kBoxSums = 8, kFilterSums = 12 };  // (filters: a^2 c in a third group of four, the last unused)
enum : int { kScalarAC = 2, kScalarA2C2 = 3, kScalarA2C = 4, kScalarStride = 4, kScalarFilterStride = 5 };

constexpr size_t kHugePage = size_t(1) << 21;

}  // namespace

void* FilmMemory::allocate(size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  const size_t rounded = (bytes + kHugePage - 1) & ~(kHugePage - 1);
  void* p = std::aligned_alloc(kHugePage, rounded);
  if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves ordinary pages
#endif
  return p;
}

void FilmMemory::deallocate(void* p, size_t bytes) {
  if (bytes < kHugePage) {
    ::operator delete(p);
  } else {
    std::free(p);
  }
}

int FilmAccumulator::sumsPerPixelFor(const FilmSettings& settings) {
  const bool scalar = settings.valueKind == ValueKind::Scalar, box = settings.filter == FilterKind::Box;
  if (scalar) return box ? kScalarStride : kScalarFilterStride;
  return (box ? kBoxSums : kFilterSums) + std::max(0, settings.spectralBins);
}

FilmAccumulator::FilmAccumulator(const FilmSettings& settings)
    : settings_(settings), filter_(settings.filter), scalar_(settings.valueKind == ValueKind::Scalar) {
  settings_.spectralBins = scalar_ ? 0 : std::max(0, settings.spectralBins);
  box_ = settings_.filter == FilterKind::Box;
  binsAt_ = box_ ? kBoxSums : kFilterSums;
  stride_ = sumsPerPixelFor(settings_);
  sums_.assign(size_t(std::max(0, settings_.width)) * std::max(0, settings_.height) * stride_, 0);
  binScratch_.assign(settings_.spectralBins, 0.0f);
}

void FilmAccumulator::clear() { std::fill(sums_.begin(), sums_.end(), 0); }

// Inline into addGeneral: returned from a call, the colour came back through the stack, and
// splat's 8-byte reload of its green and blue spanned their two stores (a store-forwarding
// stall per record).
[[gnu::always_inline]] inline FilmAccumulator::Colour FilmAccumulator::colourOf(const SampleRecord& r) const {
  const int n = std::min<int>(r.wavelengthCount, color::kMaxWavelengths);
  const color::Rgb rgb = color::xyzToLinearSrgb(color::xyzFromRadianceOverPdf(r.lambdaNm.data(), r.values.data(), n));
  return {{rgb.r, rgb.g, rgb.b}};
}

inline void FilmAccumulator::splat(int px, int py, float a, const Colour& colour, const float* bins) {
  int64_t* s = &sums_[(size_t(py) * settings_.width + px) * stride_];
  const double a64 = a, ac0 = a64 * colour.c[0], ac1 = a64 * colour.c[1], ac2 = a64 * colour.c[2];
  static_assert(kSumA2 == kSumA + 1 && kSumAC == kSumA + 2 && kSumA2C2 == kSumA + 5, "two groups of four sums");
  addFixed4(s + kSumA, a64, a64 * a, ac0, ac1);
  addFixed4(s + kSumA + 4, ac2, ac0 * ac0, ac1 * ac1, ac2 * ac2);
  if (!box_) addFixed4(s + kSumA2C, a64 * ac0, a64 * ac1, a64 * ac2, 0.0);
  for (int b = 0; b < settings_.spectralBins; ++b) addSaturating(s[binsAt_ + b], toFixed(double(a) * bins[b]));
}

inline void FilmAccumulator::splatScalar(int px, int py, float a, float value) {
  const double ac = double(a) * value;
  int64_t* s = &sums_[(size_t(py) * settings_.width + px) * stride_];
  addFixed4(s, a, double(a) * a, ac, ac * ac);
  if (!box_) addSaturating(s[kScalarA2C], toFixed(double(a) * ac));
}

// The pixels whose filter footprint covers film position (x, y) in pixel units: columns
// x0..x1, rows y0..y1, clipped to the film (empty if x0 > x1 or y0 > y1).
struct PixelSpan {
  int x0, x1, y0, y1;
};
// int(std::ceil(v)) and int(std::floor(v)) for finite v in int's range, from the truncation
// (SSE2 has no rounding instruction; these are three instructions each).
static inline int ceilToInt(float v) {
  const int i = int(v);
  return i + int(float(i) < v);
}
static inline int floorToInt(float v) {
  const int i = int(v);
  return i - int(float(i) > v);
}
// Callers pass positions on the film (finite x, y).
static inline PixelSpan footprintPixels(float radius, int width, int height, float x, float y) {
  return {std::max(0, ceilToInt(x - 0.5f - radius)), std::min(width - 1, floorToInt(x - 0.5f + radius)),
          std::max(0, ceilToInt(y - 0.5f - radius)), std::min(height - 1, floorToInt(y - 0.5f + radius))};
}

// Calls visit(px, py, weight) for every pixel whose filter footprint covers film position
// (x, y) in pixel units, with the separable filter weight times the record weight.
template <typename Visit>
static void forEachFootprintPixel(const Filter& filter, int width, int height, float x, float y, float recordWeight,
                                  Visit visit) {
  const auto [x0, x1, y0, y1] = footprintPixels(filter.radiusPixels(), width, height, x, y);
  float wx[8];
  for (int px = x0; px <= x1 && px - x0 < 8; ++px) wx[px - x0] = filter.evaluate1d(x - (float(px) + 0.5f));
  for (int py = y0; py <= y1; ++py) {
    const float wy = filter.evaluate1d(y - (float(py) + 0.5f)) * recordWeight;
    if (wy == 0.0f) continue;
    for (int px = x0; px <= x1 && px - x0 < 8; ++px) {
      const float a = wx[px - x0] * wy;
      if (a != 0.0f) visit(px, py, a);
    }
  }
}

void FilmAccumulator::add(const SampleRecord& r) {
  if (scalar_ && settings_.filter == FilterKind::Box) {
    addScalarBox(&r, 1);
  } else {
    addGeneral(r);
  }
}

void FilmAccumulator::add(const SampleRecord* records, size_t count) {
  if (scalar_ && settings_.filter == FilterKind::Box) {
    addScalarBox(records, count);
    return;
  }
  if (settings_.filter == FilterKind::Box && settings_.spectralBins == 0) {
    addColourBox(records, count);
    return;
  }
  // Records of a chunk are spread over the whole film (that is the stratification), so nearly
  // every pixel they reach misses the cache: fetch the pixels of the record kAhead places on
  // while adding this one (3 x 3 pixels for the Gaussian, one cache line each without bins).
  constexpr size_t kAhead = 8;
  for (size_t i = 0; i < count; ++i) {
    if (i + kAhead < count) prefetchFootprint(records[i + kAhead]);
    addGeneral(records[i]);
  }
}

void FilmAccumulator::prefetchFootprint(const SampleRecord& r) const {
  const int width = settings_.width, height = settings_.height;
  if (!(r.filmX >= 0.0f && r.filmX < 1.0f && r.filmY >= 0.0f && r.filmY < 1.0f)) return;  // as addGeneral
  const PixelSpan span = footprintPixels(filter_.radiusPixels(), width, height, r.filmX * float(width), r.filmY * float(height));
  if (span.x0 > span.x1) return;
  const char* const sums = reinterpret_cast<const char*>(sums_.data());
  const size_t pixelBytes = size_t(stride_) * sizeof(int64_t), rowBytes = size_t(width) * pixelBytes;
  for (int py = span.y0; py <= span.y1; ++py) {
    const char* first = sums + size_t(py) * rowBytes + size_t(span.x0) * pixelBytes;
    const char* last = sums + size_t(py) * rowBytes + size_t(span.x1 + 1) * pixelBytes - 1;
    for (const char* line = first; line < last; line += 64) __builtin_prefetch(line, 1);
    __builtin_prefetch(last, 1);  // the line of the span's last byte, when the span is not line-aligned
  }
}

// The common fast path (box filter, grey values): every record adds to one pixel. Two passes
// over the batch: first the pixel of every record, then the sums, fetching the pixel of the
// record kAhead places on while converting the current one (records of a chunk are spread over
// the whole film, which is the stratification, so nearly every record misses the cache).
void FilmAccumulator::addScalarBox(const SampleRecord* records, size_t count) {
  const int width = settings_.width, height = settings_.height;
  if (width <= 0 || height <= 0 || count == 0) return;
  constexpr uint32_t kOffFilm = 0xffffffffu;
  constexpr size_t kBatch = 4096, kAhead = 24;
  const float fw = float(width), fh = float(height);
  int64_t* const sums = sums_.data();
  if (pixelScratch_.size() < kBatch) pixelScratch_.resize(kBatch);
  uint32_t* const pixel = pixelScratch_.data();
  for (size_t first = 0; first < count; first += kBatch) {
    const SampleRecord* batch = records + first;
    const size_t n = std::min(kBatch, count - first);
    for (size_t i = 0; i < n; ++i) {
      const float fx = batch[i].filmX, fy = batch[i].filmY;
      const bool onFilm = fx >= 0.0f && fx < 1.0f && fy >= 0.0f && fy < 1.0f;  // false for NaN
      const int px = std::min(int(onFilm ? fx * fw : 0.0f), width - 1), py = std::min(int(onFilm ? fy * fh : 0.0f), height - 1);
      pixel[i] = onFilm ? uint32_t(py) * uint32_t(width) + uint32_t(px) : kOffFilm;
    }
    for (size_t i = 0; i < n; ++i) {
      if (i + kAhead < n) {
        const uint32_t ahead = pixel[i + kAhead];
        if (ahead != kOffFilm) __builtin_prefetch(sums + size_t(ahead) * kScalarStride, 1);
      }
      const uint32_t p = pixel[i];
      if (p == kOffFilm) continue;
      const SampleRecord& r = batch[i];
      const double a = r.weight, ac = a * r.values[0];
      addFixed4(sums + size_t(p) * kScalarStride, a, a * a, ac, ac * ac);
    }
  }
}

// The default colour film (box filter, no spectral bins): each record adds to the one pixel
// it falls in, as in addGeneral, in one loop without addGeneral's per-record dispatch and
// stack frame, fetching the pixel of the record kAhead places on (one cache line: 8 sums).
void FilmAccumulator::addColourBox(const SampleRecord* records, size_t count) {
  const int width = settings_.width, height = settings_.height;
  if (width <= 0 || height <= 0) return;
  const float fw = float(width), fh = float(height);
  // Whether r is on the film (false for NaN), and its pixel.
  const auto pixelOf = [&](const SampleRecord& r, int& px, int& py) {
    if (!(r.filmX >= 0.0f && r.filmX < 1.0f && r.filmY >= 0.0f && r.filmY < 1.0f)) return false;
    px = std::min(int(r.filmX * fw), width - 1);
    py = std::min(int(r.filmY * fh), height - 1);
    return true;
  };
  constexpr size_t kAhead = 8;
  const int64_t* const sums = sums_.data();
  for (size_t i = 0; i < count; ++i) {
    int px, py;
    if (i + kAhead < count && pixelOf(records[i + kAhead], px, py))
      __builtin_prefetch(sums + (size_t(py) * width + px) * stride_, 1);
    const SampleRecord& r = records[i];
    if (pixelOf(r, px, py)) splat(px, py, r.weight, colourOf(r), nullptr);
  }
}

void FilmAccumulator::addGeneral(const SampleRecord& r) {
  const int width = settings_.width, height = settings_.height;
  if (width <= 0 || height <= 0) return;
  if (!(r.filmX >= 0.0f && r.filmX < 1.0f && r.filmY >= 0.0f && r.filmY < 1.0f)) return;  // off film or NaN
  const float x = r.filmX * float(width), y = r.filmY * float(height);  // pixel units
  if (scalar_) {
    const float value = r.values[0];
    if (settings_.filter == FilterKind::Box) {
      splatScalar(std::min(int(x), width - 1), std::min(int(y), height - 1), r.weight, value);
      return;
    }
    forEachFootprintPixel(filter_, width, height, x, y, r.weight,
                          [&](int px, int py, float a) { splatScalar(px, py, a, value); });
    return;
  }
  const Colour colour = colourOf(r);
  const float* bins = nullptr;
  if (settings_.spectralBins > 0) {
    // Each wavelength's share of the group estimate, per nm of its bin.
    std::fill(binScratch_.begin(), binScratch_.end(), 0.0f);
    const int n = std::min<int>(r.wavelengthCount, color::kMaxWavelengths);
    const float binWidth = (color::kVisibleLambdaMaxNm - color::kVisibleLambdaMinNm) / settings_.spectralBins;
    for (int j = 0; j < n; ++j) {
      const int b = int((r.lambdaNm[j] - color::kVisibleLambdaMinNm) / binWidth);
      if (b >= 0 && b < settings_.spectralBins) binScratch_[b] += r.values[j] / (float(n) * binWidth);
    }
    bins = binScratch_.data();
  }
  if (settings_.filter == FilterKind::Box) {
    const int px = std::min(int(x), width - 1), py = std::min(int(y), height - 1);
    splat(px, py, r.weight, colour, bins);
    return;
  }
  forEachFootprintPixel(filter_, width, height, x, y, r.weight,
                        [&](int px, int py, float a) { splat(px, py, a, colour, bins); });
}

std::string FilmAccumulator::merge(const FilmAccumulator& other) {
  if (other.settings_.width != settings_.width || other.settings_.height != settings_.height ||
      other.stride_ != stride_ || other.settings_.filter != settings_.filter) {
    return "cannot merge films with different resolution, filter or channels";
  }
  for (size_t i = 0; i < sums_.size(); ++i) {
    if (isSaturated(other.sums_[i])) sums_[i] = other.sums_[i];
    else addSaturating(sums_[i], other.sums_[i]);
  }
  return "";
}

DevelopedImage FilmAccumulator::develop(FilmEstimator estimator, uint64_t samples) const {
  DevelopedImage image;
  image.width = settings_.width;
  image.height = settings_.height;
  image.spectralBins = settings_.spectralBins;
  image.binWidthNm = settings_.spectralBins > 0
                         ? (color::kVisibleLambdaMaxNm - color::kVisibleLambdaMinNm) / settings_.spectralBins
                         : 0.0f;
  const size_t pixels = size_t(std::max(0, image.width)) * std::max(0, image.height);
  image.rgb.assign(pixels * 3, 0.0f);
  image.variance.assign(pixels * 3, 0.0f);
  image.weightSum.assign(pixels, 0.0f);
  image.spectral.assign(pixels * image.spectralBins, 0.0f);
  const double densityScale = samples > 0 ? double(pixels) / double(samples) : 0.0;
  for (size_t p = 0; p < pixels; ++p) {
    const int64_t* s = &sums_[p * stride_];
    bool saturated = false;
    for (int k = 0; k < stride_; ++k) saturated = saturated || isSaturated(s[k]);
    image.saturatedPixels += saturated;
    const double sumA = fromFixed(s[kSumA]), sumA2 = fromFixed(s[kSumA2]);
    image.weightSum[p] = float(sumA);
    if (sumA == 0.0) continue;
    const double nEff = sumA2 > 0 ? sumA * sumA / sumA2 : 0.0;
    image.unstablePixels += sumA2 > 0 && nEff < 0.5;  // (sumA2 0: weights too small for the fixed point)
    for (int k = 0; k < 3; ++k) {
      const double sumAC = fromFixed(scalar_ ? s[kScalarAC] : s[kSumAC + k]);
      const double sumA2C2 = fromFixed(scalar_ ? s[kScalarA2C2] : s[kSumA2C2 + k]);
      // sum a^2 c: stored for filters; a box film's weights are 1 (see the layout above).
      const double sumA2C = box_ ? sumAC * (sumA2 / sumA) : fromFixed(scalar_ ? s[kScalarA2C] : s[kSumA2C + k]);
      const double mean = sumAC / sumA;
      double value, variance;
      if (estimator == FilmEstimator::Weighted) {
        // The ratio estimator's variance, sum a^2 (c - mean)^2 / (sum a)^2, with the small-sample
        // factor n / (n - 1) at n = n_eff: the filter weights correlate with the colours, which
        // the earlier (sum a c^2 / sum a - mean^2) / (n_eff - 1) ignored (tent and Gaussian
        // variances were 0.5-0.6 of the pixels' spread, Mitchell's up to 1.5 of it). One
        // sample (n_eff within rounding of 1) has no variance estimate: 0, as before.
        // Below 1024 fixed-point units of sum a^2 (a pixel reached only by the thin edges of
        // filters: a single weight under 0.008) the sums' rounding is no longer small against
        // the spread, and n_eff is unreliable: no estimate either (a single such sample got
        // variances up to 1744 on a value of 26).
        value = mean;
        const double spread = std::max(0.0, sumA2C2 - 2.0 * mean * sumA2C + mean * mean * sumA2) / (sumA * sumA);
        const bool estimable = nEff > 1.0 + 1e-3 && s[kSumA2] >= 1024;
        variance = estimable ? spread * nEff / (nEff - 1.0) : 0.0;
      } else {
        // Density: value = D sum a c with D = W H / N over the N samples of the whole film, each
        // landing anywhere: variance D^2 (sum (a c)^2 - (sum a c)^2 / N).
        value = sumAC * densityScale;
        variance = samples > 0 ? densityScale * densityScale *
                                     std::max(0.0, sumA2C2 - sumAC * sumAC / double(samples))
                               : 0.0;
      }
      image.rgb[p * 3 + k] = float(value);
      image.variance[p * 3 + k] = float(variance);
    }
    for (int b = 0; b < image.spectralBins; ++b) {
      const double sum = fromFixed(s[binsAt_ + b]);
      image.spectral[p * image.spectralBins + b] = float(estimator == FilmEstimator::Weighted ? sum / sumA : sum * densityScale);
    }
  }
  return image;
}

ExrImage DevelopedImage::toExr(bool withVariance, bool withSpectral, const std::map<std::string, std::string>& metadata) const {
  ExrImage exr;
  exr.width = width;
  exr.height = height;
  exr.metadata = metadata;
  const size_t pixels = size_t(width) * height;
  const char* names[3] = {"R", "G", "B"};
  for (int k = 0; k < 3; ++k) {
    ExrChannel c{names[k], std::vector<float>(pixels)};
    for (size_t p = 0; p < pixels; ++p) c.values[p] = rgb[p * 3 + k];
    exr.channels.push_back(std::move(c));
  }
  if (withVariance) {
    for (int k = 0; k < 3; ++k) {
      ExrChannel c{std::string("variance.") + names[k], std::vector<float>(pixels)};
      for (size_t p = 0; p < pixels; ++p) c.values[p] = variance[p * 3 + k];
      exr.channels.push_back(std::move(c));
    }
  }
  if (withSpectral) {
    for (int b = 0; b < spectralBins; ++b) {
      char name[48];
      std::snprintf(name, sizeof name, "spectral.%05.1fnm", binMinNm + (float(b) + 0.5f) * binWidthNm);
      ExrChannel c{name, std::vector<float>(pixels)};
      for (size_t p = 0; p < pixels; ++p) c.values[p] = spectral[p * spectralBins + b];
      exr.channels.push_back(std::move(c));
    }
  }
  return exr;
}

std::vector<float> DevelopedImage::relativeVarianceThumbnail(int maxSize, int& thumbWidth, int& thumbHeight) const {
  const int factor = std::max(1, (std::max(width, height) + maxSize - 1) / std::max(1, maxSize));
  thumbWidth = std::max(1, width / factor);
  thumbHeight = std::max(1, height / factor);
  std::vector<float> thumb(size_t(thumbWidth) * thumbHeight, 0.0f);
  std::vector<int> counts(thumb.size(), 0);
  for (int y = 0; y < std::min(height, thumbHeight * factor); ++y) {
    for (int x = 0; x < std::min(width, thumbWidth * factor); ++x) {
      const size_t p = size_t(y) * width + x;
      double rel = 0;
      for (int k = 0; k < 3; ++k) {
        const double m = rgb[p * 3 + k];
        rel += variance[p * 3 + k] / (m * m + 1e-4);
      }
      const size_t t = size_t(y / factor) * thumbWidth + x / factor;
      thumb[t] += float(rel / 3.0);
      counts[t]++;
    }
  }
  for (size_t t = 0; t < thumb.size(); ++t) thumb[t] = counts[t] > 0 ? thumb[t] / float(counts[t]) : 0.0f;
  return thumb;
}

}  // namespace tex
