// Film and reconstruction: filters are normalised, constant images develop exactly, images
// are bit-identical for any thread count, chunking or split of the range, and the variance
// estimate matches the true variance of a known noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <filesystem>

#include "renderer/analytic/analytic_kernel.h"
#include "renderer/color/color.h"
#include "renderer/color/spectral_to_rgb.h"
#include "renderer/film/film.h"
#include "renderer/film/film_sink.h"
#include "renderer/io/sample_file.h"
#include "renderer/sampling/pcg.h"

namespace tex {
namespace {

using runtime::IndexRange;
using runtime::SchedulerOptions;
using runtime::Sink;

FilmSettings settingsFor(int w, int h, FilterKind filter, ValueKind kind, int bins = 0) {
  FilmSettings s;
  s.width = w, s.height = h, s.filter = filter, s.valueKind = kind, s.spectralBins = bins;
  return s;
}

// Renders the analytic kernel over the ranges (one run each) with the given threads/chunk
// and returns the merged film.
FilmAccumulator render(const FilmSettings& settings, const AnalyticKernel& kernel, std::vector<IndexRange> ranges,
                       int threads, uint64_t chunk, size_t memoryBudget = FilmSink::kDefaultMemoryBudgetBytes) {
  FilmAccumulator total(settings);
  for (IndexRange range : ranges) {
    FilmSink sink(settings, memoryBudget);
    Sink<SampleRecord>* sinks[] = {&sink};
    SchedulerOptions options;
    options.threads = threads;
    options.chunkSize = chunk;
    runtime::runStream<SampleRecord>(range, options, kernel, std::span<Sink<SampleRecord>* const>(sinks));
    EXPECT_EQ(total.merge(sink.film()), "");
  }
  return total;
}

bool bitIdentical(const DevelopedImage& a, const DevelopedImage& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * 4) == 0 &&
         std::memcmp(a.variance.data(), b.variance.data(), a.variance.size() * 4) == 0 &&
         a.spectral.size() == b.spectral.size() &&
         std::memcmp(a.spectral.data(), b.spectral.data(), a.spectral.size() * 4) == 0;
}

// Slots share accumulators when one film per thread would not fit the sink's memory budget (a
// 4096^2 film is about 1 GB, and every thread had its own); films are integer sums, so the
// merged film is the same bits however the records were split.
TEST(Film, SlotsSharingAccumulatorsUnderAMemoryBudgetGiveTheSameBits) {
  const FilmSettings settings = settingsFor(64, 48, FilterKind::Gaussian, ValueKind::SpectralRadianceOverPdf, 4);
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 5), AnalyticImage::Disk,
                              ValueKind::SpectralRadianceOverPdf, 4};
  const FilmAccumulator own = render(settings, kernel, {{0, 200000}}, 4, 1000);
  const FilmAccumulator shared = render(settings, kernel, {{0, 200000}}, 4, 1000, 1);  // one accumulator for all
  EXPECT_TRUE(bitIdentical(own.develop(), shared.develop()));
  EXPECT_TRUE(own.sums() == shared.sums());
  FilmSink sink(settings, 1);
  sink.begin(8);
  EXPECT_EQ(sink.accumulatorCount(), 1);
  FilmSink roomy(settings);
  roomy.begin(8);
  EXPECT_EQ(roomy.accumulatorCount(), 8);
}

TEST(Filters, EveryFilterIntegratesToOne) {
  for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    const Filter f(kind);
    double sum = 0;
    const int n = 400;
    const double r = f.radiusPixels(), h = 2 * r / n;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) sum += f.evaluate(float(-r + (i + 0.5) * h), float(-r + (j + 0.5) * h)) * h * h;
    EXPECT_NEAR(sum, 1.0, 1e-3) << filterName(kind);
    EXPECT_EQ(f.evaluate1d(float(r) + 0.01f), 0.0f);
  }
  EXPECT_LT(Filter(FilterKind::Mitchell).evaluate1d(1.5f), 0.0f);  // the negative lobe
  EXPECT_EQ(parseFilterKind("gaussian"), FilterKind::Gaussian);
  EXPECT_FALSE(parseFilterKind("lanczos").has_value());
}

TEST(Film, ConstantImageDevelopsExactlyWithEveryFilter) {
  for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    FilmAccumulator film(settingsFor(12, 7, kind, ValueKind::Scalar));
    const sampling::Sampler sampler(sampling::SamplerKind::Sobol, 3);
    for (uint64_t i = 0; i < 20000; ++i) {
      SampleRecord r;
      const sampling::FilmPosition p = sampler.filmPosition(i);
      r.filmX = p.x, r.filmY = p.y, r.wavelengthCount = 1, r.values[0] = 0.375f;
      film.add(r);
    }
    const DevelopedImage image = film.develop();
    for (float v : image.rgb) ASSERT_NEAR(v, 0.375f, 1e-6) << filterName(kind);
    for (float v : image.variance) ASSERT_NEAR(v, 0.0f, 1e-9) << filterName(kind);
  }
}

TEST(Film, BitIdenticalForOneAndTwoThreadsAndAnyChunking) {
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 11), AnalyticImage::Disk,
                              ValueKind::SpectralRadianceOverPdf, 4};
  for (FilterKind filter : {FilterKind::Box, FilterKind::Mitchell}) {
    const FilmSettings settings = settingsFor(40, 30, filter, ValueKind::SpectralRadianceOverPdf, 8);
    const FilmAccumulator one = render(settings, kernel, {{0, 300000}}, 1, 4096);
    const FilmAccumulator two = render(settings, kernel, {{0, 300000}}, 2, 4096);
    const FilmAccumulator twoSmallChunks = render(settings, kernel, {{0, 300000}}, 2, 777);
    EXPECT_EQ(one.sums(), two.sums());
    EXPECT_EQ(one.sums(), twoSmallChunks.sums());
    EXPECT_TRUE(bitIdentical(one.develop(), two.develop()));
    EXPECT_TRUE(bitIdentical(one.develop(), twoSmallChunks.develop()));
  }
}

TEST(Film, BitIdenticalForARangeAndTheSameRangeSplitInTwoAndMerged) {
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 12), AnalyticImage::Gaussian,
                              ValueKind::SpectralRadianceOverPdf, 8};
  const FilmSettings settings = settingsFor(33, 17, FilterKind::Gaussian, ValueKind::SpectralRadianceOverPdf, 4);
  const FilmAccumulator whole = render(settings, kernel, {{1000, 201000}}, 2, 5000);
  const FilmAccumulator split = render(settings, kernel, {{1000, 77777}, {77777, 201000}}, 1, 3000);
  const FilmAccumulator splitReversed = render(settings, kernel, {{77777, 201000}, {1000, 77777}}, 2, 123);
  EXPECT_EQ(whole.sums(), split.sums());
  EXPECT_TRUE(bitIdentical(whole.develop(), split.develop()));
  EXPECT_TRUE(bitIdentical(whole.develop(), splitReversed.develop()));
  // A different range gives a different image (the comparison can fail).
  const FilmAccumulator other = render(settings, kernel, {{1001, 201000}}, 2, 5000);
  EXPECT_NE(whole.sums(), other.sums());
}

TEST(Film, BitIdenticalThroughSampleFilesDevelopedAtAnyResolution) {
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 13), AnalyticImage::Checkerboard,
                              ValueKind::SpectralRadianceOverPdf, 4};
  const std::string pathA = (std::filesystem::temp_directory_path() / "tex_film_a.samples").string();
  const std::string pathB = (std::filesystem::temp_directory_path() / "tex_film_b.samples").string();
  // Two processes' worth of work, written by two runs with 2 threads each.
  for (auto [path, range] : {std::pair{pathA, IndexRange{0, 100000}}, std::pair{pathB, IndexRange{100000, 250000}}}) {
    SampleFileWriter writer;
    SampleFileHeader header;
    header.seed = 13, header.requested = range, header.wavelengthsPerRecord = 4;
    header.compression = path == pathA ? SampleCompression::Zstd : SampleCompression::None;
    ASSERT_EQ(writer.open(path, header), "");
    SampleFileSink sink(writer);
    Sink<SampleRecord>* sinks[] = {&sink};
    SchedulerOptions options;
    options.threads = 2;
    options.chunkSize = 1000;
    runtime::runStream<SampleRecord>(range, options, kernel, std::span<Sink<SampleRecord>* const>(sinks));
    ASSERT_EQ(sink.error(), "");
  }
  for (auto [w, h] : {std::pair{16, 16}, std::pair{50, 20}}) {
    const FilmSettings settings = settingsFor(w, h, FilterKind::Tent, ValueKind::SpectralRadianceOverPdf);
    const FilmAccumulator direct = render(settings, kernel, {{0, 250000}}, 1, 250000);
    FilmAccumulator fromFiles(settings);
    for (const std::string& path : {pathB, pathA}) {
      SampleFileInfo info;
      ASSERT_EQ(readSampleFile(path, info,
                               [&](IndexRange, std::span<const SampleRecord> records) {
                                 fromFiles.add(records.data(), records.size());
                               }),
                "");
    }
    EXPECT_EQ(direct.sums(), fromFiles.sums());
    EXPECT_TRUE(bitIdentical(direct.develop(), fromFiles.develop()));
  }
  std::filesystem::remove(pathA);
  std::filesystem::remove(pathB);
}

TEST(Film, FixedPointConversionRoundsExactlyOnEveryPath) {
  // The scalar box path converts in SSE2 with a rounding trick; it must give exactly the
  // integers of round-to-nearest-even with NaN -> 0 and saturation, including at ties, for
  // huge values (the scalar fallback) and for both the batched and the single-record add.
  auto reference = [](double x) {
    double scaled = x * 16777216.0;
    if (scaled != scaled) return int64_t(0);
    return int64_t(std::llrint(std::clamp(scaled, -4.0e18, 4.0e18)));
  };
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.0f, 1.0f, -1.0f, 0.5f * 0x1p-24f, 1.5f * 0x1p-24f, 2.5f * 0x1p-24f, -2.5f * 0x1p-24f,
                          0.3f, -0.7f, 1.0e8f, -1.3e8f, 1.4e8f, 2.0e8f, 1.0e12f, -1.0e30f, inf, -inf, nan};
  const float weights[] = {1.0f, 0.25f, 3.0f, 1.0e-9f, 1.0e7f, -2.0f};
  std::vector<SampleRecord> batch;
  for (float w : weights) {
    for (float v : values) {
      SampleRecord r;
      r.filmX = 0.5f, r.filmY = 0.5f, r.weight = w, r.wavelengthCount = 1, r.values[0] = v;
      FilmAccumulator film(settingsFor(1, 1, FilterKind::Box, ValueKind::Scalar));
      film.add(r);
      const double a = w, ac = a * v;
      const int64_t expected[4] = {reference(a), reference(a * a), reference(ac), reference(ac * ac)};
      ASSERT_EQ(film.sumsPerPixel(), 4);
      for (int k = 0; k < 4; ++k) ASSERT_EQ(film.sums()[k], expected[k]) << "w " << w << " v " << v << " sum " << k;
      bool modest = true;  // sums of these cannot overflow int64
      for (int64_t e : expected) modest = modest && std::llabs(e) < (int64_t(1) << 56);
      if (modest) batch.push_back(r);
    }
  }
  ASSERT_GT(batch.size(), 40u);
  // The batched path over the same records equals the single-record adds.
  FilmAccumulator single(settingsFor(1, 1, FilterKind::Box, ValueKind::Scalar));
  FilmAccumulator batched(settingsFor(1, 1, FilterKind::Box, ValueKind::Scalar));
  for (const SampleRecord& r : batch) single.add(r);
  batched.add(batch.data(), batch.size());
  EXPECT_EQ(single.sums(), batched.sums());
}

// Sums past the fixed-point range stay at its limit instead of wrapping to the other sign
// (a 1e9 sky at 1024 spp developed to -0.074 with a variance of 0), and develop() counts the
// pixel; a merge of saturated films stays saturated. Colour, scalar and batched paths.
TEST(Film, SumsSaturateInsteadOfWrappingAndDevelopCountsThePixels) {
  for (const ValueKind kind : {ValueKind::Scalar, ValueKind::SpectralRadianceOverPdf}) {
    FilmAccumulator film(settingsFor(2, 1, FilterKind::Box, kind));
    std::vector<SampleRecord> batch;
    for (int i = 0; i < 2048; ++i) {
      SampleRecord r;
      r.filmX = 0.25f, r.filmY = 0.5f, r.weight = 1.0f;
      r.wavelengthCount = kind == ValueKind::Scalar ? 1 : 4;
      for (int j = 0; j < 4; ++j) r.lambdaNm[size_t(j)] = 450.0f + 50.0f * j, r.values[size_t(j)] = 1.0e9f;
      batch.push_back(r);
      SampleRecord dim = r;  // the other pixel stays in range
      dim.filmX = 0.75f;
      for (int j = 0; j < 4; ++j) dim.values[size_t(j)] = 0.5f;
      batch.push_back(dim);
    }
    film.add(batch.data(), batch.size());
    for (const SampleRecord& r : batch) film.add(r);
    const DevelopedImage image = film.develop();
    EXPECT_EQ(image.saturatedPixels, 1u);
    for (int k = 0; k < 3; ++k) {
      if (kind == ValueKind::Scalar && k > 0) break;
      EXPECT_GT(image.rgb[size_t(k)], 0.0f) << "wrapped to the other sign";
    }
    FilmAccumulator other(settingsFor(2, 1, FilterKind::Box, kind));
    other.add(batch.data(), batch.size());
    EXPECT_EQ(film.merge(other), "");
    EXPECT_EQ(film.develop().saturatedPixels, 1u);
    FilmAccumulator modest(settingsFor(2, 1, FilterKind::Box, kind));
    modest.add(batch.data() + 1, 1);
    EXPECT_EQ(modest.develop().saturatedPixels, 0u);
  }
}

// Developing a Mitchell film from far fewer samples than pixels leaves pixels whose weights
// nearly cancel (values in the thousands on a constant image); develop() counts them so that
// the CLI can warn. Positive filters never have any.
TEST(Film, PixelsWhoseFilterWeightsCancelAreCounted) {
  for (const FilterKind filter : {FilterKind::Mitchell, FilterKind::Box, FilterKind::Gaussian}) {
    FilmAccumulator film(settingsFor(128, 128, filter, ValueKind::Scalar));
    sampling::Pcg32 rng(5, 7);
    for (int i = 0; i < 4096; ++i) {
      SampleRecord r;
      r.filmX = rng.nextFloat(), r.filmY = rng.nextFloat(), r.weight = 1.0f, r.wavelengthCount = 1;
      r.values[0] = 1.0f;
      film.add(r);
    }
    const DevelopedImage image = film.develop();
    if (filter == FilterKind::Mitchell) EXPECT_GT(image.unstablePixels, 100u);
    else EXPECT_EQ(image.unstablePixels, 0u) << filterName(filter);
  }
}

TEST(Film, ColourSplatRoundsExactlyLikeTheScalarConversion) {
  // Colour films convert their eight sums four at a time (SSE2); the integers must be those of
  // round-to-nearest-even with NaN -> 0 and saturation, the huge values' fallback included.
  auto reference = [](double x) {
    double scaled = x * 16777216.0;
    if (scaled != scaled) return int64_t(0);
    return int64_t(std::llrint(std::clamp(scaled, -4.0e18, 4.0e18)));
  };
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.0f, 1.0f, 0.3f, -0.7f, 1.5f * 0x1p-24f, 1.0e8f, 3.0e9f, 1.0e12f, -1.0e30f, inf, nan};
  const float weights[] = {1.0f, 0.25f, 3.0f, 1.0e-9f, 1.0e7f, -2.0f};
  int checked = 0;
  for (float w : weights) {
    for (float v : values) {
      SampleRecord r;
      r.filmX = 0.5f, r.filmY = 0.5f, r.weight = w, r.wavelengthCount = 4;
      r.lambdaNm = {450.0f, 530.0f, 600.0f, 650.0f};
      r.values = {v, 0.5f * v, 0.25f, 2.0f * v};
      FilmAccumulator film(settingsFor(1, 1, FilterKind::Box, ValueKind::SpectralRadianceOverPdf));
      film.add(r);
      const color::Rgb rgb = color::xyzToLinearSrgb(color::xyzFromRadianceOverPdf(r.lambdaNm.data(), r.values.data(), 4));
      const double a = w, c[3] = {rgb.r, rgb.g, rgb.b};
      const int64_t expected[8] = {reference(a),        reference(a * a),           reference(a * c[0]),
                                   reference(a * c[1]), reference(a * c[2]),        reference(a * c[0] * (a * c[0])),
                                   reference(a * c[1] * (a * c[1])), reference(a * c[2] * (a * c[2]))};
      ASSERT_EQ(film.sumsPerPixel(), 8);
      for (int k = 0; k < 8; ++k) ASSERT_EQ(film.sums()[k], expected[k]) << "w " << w << " v " << v << " sum " << k;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 66);
}

TEST(Film, BatchedAddEqualsSingleAddsForEveryFilter) {
  // The batched add fetches pixels ahead of the records it adds; records at the film's edges,
  // off it and at NaN positions must neither fault nor change a sum.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<SampleRecord> records;
  for (uint64_t i = 0; i < 3000; ++i) {
    SampleRecord r;
    r.filmX = sampling::randomUniform(7, i, 0), r.filmY = sampling::randomUniform(7, i, 1);
    if (i % 50 == 0) r.filmX = 0.0f;
    if (i % 70 == 0) r.filmY = 0.99999994f;
    if (i % 90 == 0) r.filmX = 1.25f;
    if (i % 110 == 0) r.filmY = nan;
    if (i % 130 == 0) r.filmX = -0.5f;
    r.weight = 0.5f + sampling::randomUniform(7, i, 2);
    r.wavelengthCount = 4;
    r.lambdaNm = {420.0f, 510.0f, 580.0f, 640.0f};
    for (int j = 0; j < 4; ++j) r.values[size_t(j)] = sampling::randomUniform(7, i, 3 + j);
    records.push_back(r);
  }
  for (FilterKind filter : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    for (ValueKind kind : {ValueKind::SpectralRadianceOverPdf, ValueKind::Scalar}) {
      const FilmSettings settings = settingsFor(37, 23, filter, kind, kind == ValueKind::Scalar ? 0 : 3);
      FilmAccumulator single(settings), batched(settings);
      for (const SampleRecord& r : records) single.add(r);
      batched.add(records.data(), records.size());
      EXPECT_EQ(single.sums(), batched.sums()) << filterName(filter);
      EXPECT_NE(std::count(single.sums().begin(), single.sums().end(), int64_t(0)), int64_t(single.sums().size()));
    }
  }
}

TEST(Film, FilteredSplatEqualsABruteForceSplatOverEveryPixel) {
  // Each record adds a = k(dx) (k(dy) w) to every pixel whose filter weight is not zero: the
  // film's footprint (from the record's position and the filter radius) must find them all,
  // at pixel corners, centres and edges of the film too.
  auto reference = [](double x) { return int64_t(std::llrint(x * 16777216.0)); };
  const int w = 9, h = 7;
  std::vector<std::pair<float, float>> positions = {{0.0f, 0.0f}, {0.5f, 0.5f}, {1.0f / 9.0f, 3.0f / 7.0f},
                                                    {4.5f / 9.0f, 2.0f / 7.0f}, {8.999f / 9.0f, 6.999f / 7.0f}};
  for (int i = 0; i < 200; ++i)
    positions.push_back({sampling::randomUniform(21, uint64_t(i), 0), sampling::randomUniform(21, uint64_t(i), 1)});
  for (FilterKind kind : {FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    const Filter filter(kind);
    FilmAccumulator film(settingsFor(w, h, kind, ValueKind::Scalar));
    std::vector<int64_t> expected(size_t(w * h * 5), 0);  // a, a^2, a c, a^2 c^2, a^2 c
    for (size_t i = 0; i < positions.size(); ++i) {
      SampleRecord r;
      r.filmX = positions[i].first, r.filmY = positions[i].second, r.weight = 0.75f, r.wavelengthCount = 1;
      r.values[0] = 0.25f + 0.01f * float(i);
      film.add(r);
      const float x = r.filmX * float(w), y = r.filmY * float(h);
      for (int py = 0; py < h; ++py) {
        for (int px = 0; px < w; ++px) {
          const float a = filter.evaluate1d(x - (float(px) + 0.5f)) * (filter.evaluate1d(y - (float(py) + 0.5f)) * r.weight);
          if (a == 0.0f) continue;
          const double ac = double(a) * r.values[0];
          int64_t* e = &expected[size_t(py * w + px) * 5];
          e[0] += reference(a), e[1] += reference(double(a) * a), e[2] += reference(ac), e[3] += reference(ac * ac);
          e[4] += reference(double(a) * ac);
        }
      }
    }
    EXPECT_EQ(std::vector<int64_t>(film.sums().begin(), film.sums().end()), expected) << filterName(kind);
  }
}

TEST(Film, VarianceEstimateMatchesKnownNoise) {
  // Uniform noise in [0,1) has variance 1/12; with n samples per pixel (box filter, Sobol
  // positions give exactly n per pixel) the pixel estimate's variance is 1/(12 n).
  const int w = 16, h = 16, perPixel = 64;
  FilmAccumulator film(settingsFor(w, h, FilterKind::Box, ValueKind::Scalar));
  const sampling::Sampler positions(sampling::SamplerKind::Sobol, 1);
  for (uint64_t i = 0; i < uint64_t(w * h * perPixel); ++i) {
    SampleRecord r;
    const sampling::FilmPosition p = positions.filmPosition(i);
    r.filmX = p.x, r.filmY = p.y, r.wavelengthCount = 1;
    r.values[0] = sampling::randomUniform(2, i, 0);
    film.add(r);
  }
  const DevelopedImage image = film.develop();
  double meanVariance = 0, meanValue = 0;
  for (size_t p = 0; p < size_t(w * h); ++p) meanVariance += image.variance[p * 3], meanValue += image.rgb[p * 3];
  meanVariance /= w * h;
  meanValue /= w * h;
  EXPECT_NEAR(meanValue, 0.5, 0.01);
  EXPECT_NEAR(meanVariance, 1.0 / (12.0 * perPixel), 0.05 / (12.0 * perPixel));
  int tw = 0, th = 0;
  const std::vector<float> thumb = image.relativeVarianceThumbnail(4, tw, th);
  EXPECT_EQ(tw, 4);
  EXPECT_EQ(th, 4);
  for (float t : thumb) EXPECT_NEAR(t, (1.0 / (12.0 * perPixel)) / (0.25 + 1e-4), 0.01);
}

// The variance channels predict how pixel values spread between independent renders, for every
// filter and both estimators: 300 seeds of independent uniform sample positions over a 12 x 12
// scalar film with a value that varies with the position (so the filter weights correlate with
// the values) plus uniform noise. Pooled over the pixels, the empirical variance across seeds
// over the mean variance channel must be 1 within its sampling error (the ratio's standard
// deviation is about sqrt(2 / 299) / 12 per pool ... < 0.01; 0.05 allows for the variance
// estimator's own small-sample bias). The earlier formula ignored the weights' correlation
// with the values: tent 0.61, Gaussian 0.54, Mitchell 1.02 pooled (1.54 per pixel), density
// estimator 130.
TEST(Film, VarianceChannelsPredictTheSpreadBetweenIndependentRendersForEveryFilter) {
  const int w = 12, h = 12, perPixel = 48, seeds = 300;
  const uint64_t samples = uint64_t(w * h * perPixel);
  for (FilterKind filter : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    for (FilmEstimator estimator : {FilmEstimator::Weighted, FilmEstimator::Density}) {
      std::vector<double> sum(size_t(w * h), 0.0), sumSquares(size_t(w * h), 0.0), meanChannel(size_t(w * h), 0.0);
      for (int seed = 0; seed < seeds; ++seed) {
        FilmAccumulator film(settingsFor(w, h, filter, ValueKind::Scalar));
        sampling::Pcg32 rng(uint64_t(seed) + 1000, 7);
        for (uint64_t i = 0; i < samples; ++i) {
          SampleRecord r;
          r.filmX = rng.nextFloat(), r.filmY = rng.nextFloat(), r.wavelengthCount = 1;
          r.values[0] = 4.0f * r.filmX + 2.0f * r.filmY * r.filmY + rng.nextFloat();
          film.add(r);
        }
        const DevelopedImage image = film.develop(estimator, samples);
        for (size_t p = 0; p < size_t(w * h); ++p) {
          sum[p] += image.rgb[p * 3];
          sumSquares[p] += double(image.rgb[p * 3]) * image.rgb[p * 3];
          meanChannel[p] += image.variance[p * 3] / seeds;
        }
      }
      double empirical = 0, predicted = 0;
      for (size_t p = 0; p < size_t(w * h); ++p) {
        empirical += (sumSquares[p] - sum[p] * sum[p] / seeds) / (seeds - 1);
        predicted += meanChannel[p];
      }
      EXPECT_NEAR(empirical / predicted, 1.0, 0.05)
          << "filter " << int(filter) << (estimator == FilmEstimator::Weighted ? " weighted" : " density");
    }
  }
}

// A pixel reached by a single sample has no variance estimate: 0 (its n_eff, from rounded
// fixed-point sums, had come out a hair above 1 and divided rounding noise by 1e-7: variances
// up to 1744 on a value of 26 when 1 spp was developed at twice the resolution with a tent).
// The pixels with one contribution are found by brute force over the filter's footprint.
TEST(Film, PixelsReachedByOneSampleHaveNoVarianceEstimate) {
  const int w = 48, h = 48;
  for (FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
    const Filter filter(kind);
    FilmAccumulator film(settingsFor(w, h, kind, ValueKind::Scalar));
    std::vector<int> contributions(size_t(w * h), 0);
    sampling::Pcg32 rng(5, 1);
    for (int i = 0; i < w * h / 4; ++i) {  // a quarter sample per pixel, at random values
      SampleRecord r;
      r.filmX = rng.nextFloat(), r.filmY = rng.nextFloat(), r.wavelengthCount = 1;
      r.values[0] = 30.0f * rng.nextFloat();
      film.add(r);
      const float x = r.filmX * float(w), y = r.filmY * float(h);
      for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
          const float a = kind == FilterKind::Box
                              ? float(int(x) == px && int(y) == py)
                              : filter.evaluate1d(x - (float(px) + 0.5f)) * filter.evaluate1d(y - (float(py) + 0.5f));
          contributions[size_t(py * w + px)] += a != 0.0f;
        }
    }
    const DevelopedImage image = film.develop();
    int single = 0;
    for (size_t p = 0; p < size_t(w * h); ++p) {
      if (contributions[p] != 1) continue;
      ++single;
      for (int k = 0; k < 3; ++k) EXPECT_EQ(image.variance[p * 3 + k], 0.0f) << filterName(kind) << " pixel " << p;
    }
    EXPECT_GT(single, 100) << filterName(kind);
  }
}

TEST(Film, DensityEstimatorAgreesWithWeightedForUniformSamples) {
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 4), AnalyticImage::Gaussian};
  const FilmSettings settings = settingsFor(8, 8, FilterKind::Box, ValueKind::Scalar);
  const FilmAccumulator film = render(settings, kernel, {{0, 1 << 16}}, 1, 1 << 16);
  const DevelopedImage weighted = film.develop(FilmEstimator::Weighted);
  const DevelopedImage density = film.develop(FilmEstimator::Density, 1 << 16);
  for (size_t i = 0; i < weighted.rgb.size(); ++i) EXPECT_NEAR(weighted.rgb[i], density.rgb[i], 1e-5);
}

TEST(Film, SpectralRecordsOfAGreySpectrumDevelopToGrey) {
  const AnalyticKernel kernel{sampling::Sampler(sampling::SamplerKind::Sobol, 5), AnalyticImage::Gaussian,
                              ValueKind::SpectralRadianceOverPdf, 8};
  const FilmSettings settings = settingsFor(8, 8, FilterKind::Box, ValueKind::SpectralRadianceOverPdf, 4);
  const DevelopedImage image = render(settings, kernel, {{0, 1 << 18}}, 2, 4096).develop();
  const std::vector<double> exact = exactPixelAverages(AnalyticImage::Gaussian, 8, 8);
  for (size_t p = 0; p < exact.size(); ++p)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(image.rgb[p * 3 + k], exact[p], 0.01 + 0.01 * exact[p]) << p << " " << k;
  EXPECT_EQ(image.spectralBins, 4);
  const ExrImage exr = image.toExr(true, true, {{"samples", "262144"}});
  EXPECT_EQ(exr.channels.size(), 3u + 3u + 4u);
  EXPECT_NE(exr.find("variance.G"), nullptr);
}

}  // namespace
}  // namespace tex
