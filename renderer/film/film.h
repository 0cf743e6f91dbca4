// The film: accumulates sample records into pixels at one resolution with one filter, and
// develops them into an image. Accumulation is in 64-bit fixed point (2^-24 units), so it is
// exact integer addition: the result does not depend on the order records arrive in, on the
// thread count, or on how the index range was split (films merge by adding integers).
//
// Per pixel it keeps, with a = filter(x - centre) * record weight and c the record's colour
// (linear sRGB, or grey for scalar records): sum a, sum a^2, and per colour channel sum a c,
// sum a^2 c^2 and (filters other than box) sum a^2 c; and sum a s_b per spectral bin. A scalar
// film keeps one grey channel instead of three equal ones. Developing gives
//   colour    = sum a c / sum a                          (the weighted estimator), or
//             = sum a c * D, D = W H / N                 (the density estimator, N samples),
//   variance  = sum a^2 (c - colour)^2 / (sum a)^2 * n_eff / (n_eff - 1),  n_eff = (sum a)^2 / sum a^2
//             (weighted: the ratio estimator's), or D^2 (sum a^2 c^2 - (sum a c)^2 / N) (density),
// an estimate of the variance of the pixel value (it treats samples as independent, so it
// overestimates the error of QMC samples).
#pragma once
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <vector>

#include "renderer/film/filters.h"
#include "renderer/film/sample_record.h"
#include "renderer/image/image_io.h"

namespace tex {

enum class FilmEstimator { Weighted, Density };

struct FilmSettings {
  int width = 0, height = 0;
  FilterKind filter = FilterKind::Box;
  ValueKind valueKind = ValueKind::SpectralRadianceOverPdf;
  int spectralBins = 0;  // 0: none; else equal-width bins over 360..830 nm (spectral records only)
};

// The developed image: linear sRGB, its variance, optional spectral bins (all top row first).
struct DevelopedImage {
  int width = 0, height = 0;
  std::vector<float> rgb;       // 3 per pixel
  std::vector<float> variance;  // 3 per pixel: variance of the pixel estimate
  std::vector<float> weightSum; // 1 per pixel: sum of filter weights (0: no sample reached it)
  int spectralBins = 0;
  std::vector<float> spectral;  // spectralBins per pixel: mean radiance over each bin
  float binMinNm = 360, binWidthNm = 0;
  // Pixels with a sum at the film's fixed-point limit (about 5.5e11 per pixel; sums of squares
  // for the variance get there first): their values are wrong and must be reported.
  uint64_t saturatedPixels = 0;
  // Pixels whose filter weights nearly cancel (a negative-lobed filter such as Mitchell with
  // few samples: effective sample count (sum a)^2 / sum a^2 below 1/2), so that the weighted
  // mean divides by almost nothing (-21 .. 19.5 on a constant sky at 1 spp). Reported.
  uint64_t unstablePixels = 0;

  RgbImage rgbImage() const { return {width, height, rgb}; }
  // EXR channels R, G, B [, variance.R/G/B] [, spectral.<centre>nm ...] with metadata.
  ExrImage toExr(bool withVariance, bool withSpectral, const std::map<std::string, std::string>& metadata) const;
  // Mean over channels of variance / colour^2, box-downsampled to at most maxSize pixels on
  // the longer side (the relative-variance thumbnail).
  std::vector<float> relativeVarianceThumbnail(int maxSize, int& thumbWidth, int& thumbHeight) const;
};

// The allocator of the film's sums: blocks of 2 MB and more are 2 MB aligned and advised as
// transparent huge pages (Linux), so that splatting at random positions over a large film does
// not also miss the TLB on every record. Smaller blocks use the ordinary allocator.
struct FilmMemory {
  static void* allocate(size_t bytes);
  static void deallocate(void* p, size_t bytes);
};
template <class T>
struct FilmAllocator {
  using value_type = T;
  FilmAllocator() = default;
  template <class U>
  FilmAllocator(const FilmAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(FilmMemory::allocate(n * sizeof(T))); }
  void deallocate(T* p, size_t n) { FilmMemory::deallocate(p, n * sizeof(T)); }
  friend bool operator==(const FilmAllocator&, const FilmAllocator&) { return true; }
};
using FilmSums = std::vector<int64_t, FilmAllocator<int64_t>>;

class FilmAccumulator {
 public:
  explicit FilmAccumulator(const FilmSettings& settings);

  const FilmSettings& settings() const { return settings_; }
  void add(const SampleRecord& record);
  void add(const SampleRecord* records, size_t count);
  // Adds another film's sums (same settings). Exact and order-independent.
  std::string merge(const FilmAccumulator& other);
  void clear();

  // samples: the number of sample indices behind the records (for the density estimator).
  DevelopedImage develop(FilmEstimator estimator = FilmEstimator::Weighted, uint64_t samples = 0) const;

  // The raw fixed-point sums (for bit-identity tests).
  const FilmSums& sums() const { return sums_; }
  int sumsPerPixel() const { return stride_; }
  // What sumsPerPixel() will be for a film of these settings (before allocating one).
  static int sumsPerPixelFor(const FilmSettings& settings);

 private:
  struct Colour {
    float c[3];
  };
  Colour colourOf(const SampleRecord& r) const;
  void addGeneral(const SampleRecord& record);
  void addScalarBox(const SampleRecord* records, size_t count);
  void addColourBox(const SampleRecord* records, size_t count);
  void prefetchFootprint(const SampleRecord& record) const;
  void splat(int px, int py, float a, const Colour& colour, const float* bins);
  void splatScalar(int px, int py, float a, float value);

  FilmSettings settings_;
  Filter filter_;
  bool scalar_;  // one grey channel: sums a, a^2, a c, a^2 c^2 [, a^2 c]
  bool box_;     // box filter: sum a^2 c is not stored (record weights are 1)
  int binsAt_;   // where the spectral bins' sums start: 8 (box) or 12
  int stride_;   // int64 sums per pixel: scalar 4 (box) or 5, else binsAt_ + bins
  FilmSums sums_;
  std::vector<float> binScratch_;
  std::vector<uint32_t> pixelScratch_;  // the scalar box path's pixel offsets of one batch
};

}  // namespace tex
