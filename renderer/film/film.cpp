#include "renderer/film/film.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// Layout of one pixel's sums.
enum : int { kSumA = 0, kSumA2 = 1, kSumAC = 2, kSumAC2 = 5, kSumBins = 8 };

}  // namespace

FilmAccumulator::FilmAccumulator(const FilmSettings& settings)
    : settings_(settings), filter_(settings.filter), stride_(kSumBins + std::max(0, settings.spectralBins)) {
  settings_.spectralBins = std::max(0, settings.spectralBins);
  if (settings_.valueKind == ValueKind::Scalar) settings_.spectralBins = 0, stride_ = kSumBins;
  sums_.assign(size_t(std::max(0, settings_.width)) * std::max(0, settings_.height) * stride_, 0);
  binScratch_.assign(settings_.spectralBins, 0.0f);
}

void FilmAccumulator::clear() { std::fill(sums_.begin(), sums_.end(), 0); }

FilmAccumulator::Colour FilmAccumulator::colourOf(const SampleRecord& r) const {
  if (settings_.valueKind == ValueKind::Scalar) return {{r.values[0], r.values[0], r.values[0]}};
  const int n = std::min<int>(r.wavelengthCount, color::kMaxWavelengths);
  const color::Rgb rgb = color::xyzToLinearSrgb(color::xyzFromRadianceOverPdf(r.lambdaNm.data(), r.values.data(), n));
  return {{rgb.r, rgb.g, rgb.b}};
}

inline void FilmAccumulator::splat(int px, int py, float a, const Colour& colour, const float* bins) {
  int64_t* s = &sums_[(size_t(py) * settings_.width + px) * stride_];
  s[kSumA] += toFixed(a);
  s[kSumA2] += toFixed(double(a) * a);
  for (int k = 0; k < 3; ++k) {
    const double ac = double(a) * colour.c[k];
    s[kSumAC + k] += toFixed(ac);
    s[kSumAC2 + k] += toFixed(ac * colour.c[k]);
  }
  for (int b = 0; b < settings_.spectralBins; ++b) s[kSumBins + b] += toFixed(double(a) * bins[b]);
}

void FilmAccumulator::add(const SampleRecord& r) {
  const int width = settings_.width, height = settings_.height;
  if (width <= 0 || height <= 0) return;
  if (!(r.filmX >= 0.0f && r.filmX < 1.0f && r.filmY >= 0.0f && r.filmY < 1.0f)) return;  // off film or NaN
  const float x = r.filmX * float(width), y = r.filmY * float(height);  // pixel units
  if (settings_.filter == FilterKind::Box && settings_.valueKind == ValueKind::Scalar) {
    // The common fast path: one pixel, one grey value.
    const int px = std::min(int(x), width - 1), py = std::min(int(y), height - 1);
    int64_t* s = &sums_[(size_t(py) * width + px) * stride_];
    const double a = r.weight, ac = a * r.values[0];
    const int64_t fa = toFixed(a), fa2 = toFixed(a * a), fac = toFixed(ac), fac2 = toFixed(ac * r.values[0]);
    s[kSumA] += fa, s[kSumA2] += fa2;
    s[kSumAC] += fac, s[kSumAC + 1] += fac, s[kSumAC + 2] += fac;
    s[kSumAC2] += fac2, s[kSumAC2 + 1] += fac2, s[kSumAC2 + 2] += fac2;
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
  const float radius = filter_.radiusPixels();
  const int x0 = std::max(0, int(std::ceil(x - 0.5f - radius))), x1 = std::min(width - 1, int(std::floor(x - 0.5f + radius)));
  const int y0 = std::max(0, int(std::ceil(y - 0.5f - radius))), y1 = std::min(height - 1, int(std::floor(y - 0.5f + radius)));
  float wx[8];
  for (int px = x0; px <= x1 && px - x0 < 8; ++px) wx[px - x0] = filter_.evaluate1d(x - (float(px) + 0.5f));
  for (int py = y0; py <= y1; ++py) {
    const float wy = filter_.evaluate1d(y - (float(py) + 0.5f)) * r.weight;
    if (wy == 0.0f) continue;
    for (int px = x0; px <= x1 && px - x0 < 8; ++px) {
      const float a = wx[px - x0] * wy;
      if (a != 0.0f) splat(px, py, a, colour, bins);
    }
  }
}

void FilmAccumulator::add(const SampleRecord* records, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    // Records of a chunk are spread over the whole film (that is the stratification), so
    // fetch the next records' pixels early.
    if (i + 8 < count && settings_.filter == FilterKind::Box) {
      const SampleRecord& ahead = records[i + 8];
      const int px = std::clamp(int(ahead.filmX * settings_.width), 0, settings_.width - 1);
      const int py = std::clamp(int(ahead.filmY * settings_.height), 0, settings_.height - 1);
      __builtin_prefetch(&sums_[(size_t(py) * settings_.width + px) * stride_], 1);
    }
    add(records[i]);
  }
}

std::string FilmAccumulator::merge(const FilmAccumulator& other) {
  if (other.settings_.width != settings_.width || other.settings_.height != settings_.height ||
      other.stride_ != stride_ || other.settings_.filter != settings_.filter) {
    return "cannot merge films with different resolution, filter or channels";
  }
  for (size_t i = 0; i < sums_.size(); ++i) sums_[i] += other.sums_[i];
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
    const double sumA = fromFixed(s[kSumA]), sumA2 = fromFixed(s[kSumA2]);
    image.weightSum[p] = float(sumA);
    if (sumA == 0.0) continue;
    const double nEff = sumA2 > 0 ? sumA * sumA / sumA2 : 0.0;
    for (int k = 0; k < 3; ++k) {
      const double mean = fromFixed(s[kSumAC + k]) / sumA;
      const double secondMoment = fromFixed(s[kSumAC2 + k]) / sumA;
      const double value = estimator == FilmEstimator::Weighted ? mean : fromFixed(s[kSumAC + k]) * densityScale;
      image.rgb[p * 3 + k] = float(value);
      image.variance[p * 3 + k] = nEff > 1.0 ? float(std::max(0.0, secondMoment - mean * mean) / (nEff - 1.0)) : 0.0f;
    }
    for (int b = 0; b < image.spectralBins; ++b) {
      const double sum = fromFixed(s[kSumBins + b]);
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
