// The analytic kernel proves the whole chain (sampler -> runtime -> film): the error of the
// developed image against the exact pixel averages falls with the expected slope in N.
// Scrambled Sobol on a smooth image: faster than N^-0.85 (theory: about N^-1.5 for nets on
// smooth integrands); on images with edges: faster than N^-0.65 (theory: N^-0.75); the random
// baseline: N^-0.5 within 0.1.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/analytic/analytic_kernel.h"
#include "renderer/film/film_sink.h"

namespace tex {
namespace {

double rmseAgainstExact(AnalyticImage image, sampling::SamplerKind kind, uint64_t seed, uint64_t samples, int res) {
  FilmSettings settings;
  settings.width = settings.height = res;
  settings.valueKind = ValueKind::Scalar;
  FilmSink sink(settings);
  runtime::Sink<SampleRecord>* sinks[] = {&sink};
  runtime::SchedulerOptions options;
  options.threads = 2;
  const AnalyticKernel kernel{sampling::Sampler(kind, seed), image, ValueKind::Scalar};
  runtime::runStream<SampleRecord>({0, samples}, options, kernel, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  const DevelopedImage developed = sink.film().develop();
  const std::vector<double> exact = exactPixelAverages(image, res, res);
  double sum = 0;
  for (size_t p = 0; p < exact.size(); ++p) sum += (developed.rgb[p * 3] - exact[p]) * (developed.rgb[p * 3] - exact[p]);
  return std::sqrt(sum / double(exact.size()));
}

// Least-squares slope of log(rmse) against log(N), RMSE averaged (in the mean-square sense)
// over independent seeds.
double fittedSlope(AnalyticImage image, sampling::SamplerKind kind) {
  const int res = 16, seeds = 4;
  std::vector<double> xs, ys;
  for (int log2n = 12; log2n <= 20; log2n += 2) {
    double meanSquare = 0;
    for (int s = 0; s < seeds; ++s) {
      const double e = rmseAgainstExact(image, kind, 1000 + s, uint64_t(1) << log2n, res);
      meanSquare += e * e / seeds;
    }
    xs.push_back(log2n * std::log(2.0));
    ys.push_back(0.5 * std::log(meanSquare));
  }
  const double n = double(xs.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < xs.size(); ++i) sx += xs[i], sy += ys[i], sxx += xs[i] * xs[i], sxy += xs[i] * ys[i];
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(AnalyticConvergence, SobolOnTheSmoothGaussianIsFasterThanNToMinus085) {
  const double slope = fittedSlope(AnalyticImage::Gaussian, sampling::SamplerKind::Sobol);
  RecordProperty("slope", std::to_string(slope));
  EXPECT_LT(slope, -0.85);
}

TEST(AnalyticConvergence, SobolOnImagesWithEdgesIsFasterThanNToMinus065) {
  for (AnalyticImage image : {AnalyticImage::Disk, AnalyticImage::Checkerboard, AnalyticImage::Step}) {
    const double slope = fittedSlope(image, sampling::SamplerKind::Sobol);
    EXPECT_LT(slope, -0.65) << analyticImageName(image);
  }
}

TEST(AnalyticConvergence, RandomBaselineConvergesAsNToMinusHalf) {
  for (AnalyticImage image : kAllAnalyticImages) {
    const double slope = fittedSlope(image, sampling::SamplerKind::Random);
    EXPECT_NEAR(slope, -0.5, 0.1) << analyticImageName(image);
  }
}

TEST(AnalyticConvergence, ExactPixelAveragesAgreeWithBruteForce) {
  // Independent check of the reference images: a 200x200 midpoint grid per pixel.
  for (AnalyticImage image : kAllAnalyticImages) {
    const std::vector<double> exact = exactPixelAverages(image, 4, 4);
    for (int p : {0, 5, 10}) {
      const int px = p % 4, py = p / 4;
      double sum = 0;
      for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j) sum += analyticValue(image, (px + (i + 0.5f) / 200) / 4, (py + (j + 0.5f) / 200) / 4);
      EXPECT_NEAR(exact[p], sum / 40000, 3e-3) << analyticImageName(image) << " pixel " << p;
    }
  }
}

}  // namespace
}  // namespace tex
