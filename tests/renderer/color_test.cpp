// Colour science: the CIE tables, the XYZ/sRGB matrices, the visible-wavelength density and
// the group estimators.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/color/cie_tables.h"
#include "renderer/color/color.h"
#include "renderer/color/spectral_to_rgb.h"
#include "renderer/color/wavelengths.h"
#include "renderer/sampling/pcg.h"
#include "tests/renderer/chi_square.h"

namespace tex::color {
namespace {

TEST(CieTables, PublishedValuesAndIntegrals) {
  // Spot values of the CIE 1931 2-degree observer (CIE 15:2004 table).
  EXPECT_FLOAT_EQ(cieXyzBar(555.0f).y, 1.0f);
  EXPECT_NEAR(cieXyzBar(600.0f).x, 1.0622f, 1e-4);
  EXPECT_NEAR(cieXyzBar(450.0f).z, 1.7721f, 1e-4);
  double sx = 0, sy = 0, sz = 0;
  for (int i = 0; i < kCieSampleCount; ++i) sx += kCie1931X[i], sy += kCie1931Y[i], sz += kCie1931Z[i];
  EXPECT_NEAR(sy, kCie1931YIntegralNm, 1e-4);
  // An equal-energy spectrum has equal tristimulus values (to the table's rounding).
  EXPECT_NEAR(sx / sy, 1.0, 1e-3);
  EXPECT_NEAR(sz / sy, 1.0, 1e-3);
  EXPECT_EQ(cieXyzBar(359.0f).y, 0.0f);
  EXPECT_EQ(cieXyzBar(831.0f).x, 0.0f);
  EXPECT_FLOAT_EQ(d65RelativePower(560.0f), 100.0f);
}

TEST(Color, SrgbMatricesAreInversesAndD65IsWhite) {
  Rgb rgb{0.2f, 0.5f, 0.9f};
  Rgb back = xyzToLinearSrgb(linearSrgbToXyz(rgb));
  EXPECT_NEAR(back.r, rgb.r, 1e-5);
  EXPECT_NEAR(back.g, rgb.g, 1e-5);
  EXPECT_NEAR(back.b, rgb.b, 1e-5);
  // A perfect white reflector under D65 is sRGB white.
  Rgb white = xyzToLinearSrgb(reflectanceSpectrumToXyz([](float) { return 1.0f; }));
  EXPECT_NEAR(white.r, 1.0f, 2e-3);
  EXPECT_NEAR(white.g, 1.0f, 2e-3);
  EXPECT_NEAR(white.b, 1.0f, 2e-3);
  EXPECT_NEAR(radianceSpectrumToXyz([](float) { return 1.0f; }).y, 1.0f, 1e-6);
}

TEST(Wavelengths, DensityMatchesThePublishedConstantsAndIntegratesToOne) {
  // The published form: 0.0039398 / cosh^2(0.0072 (lambda - 538)).
  for (float lambda : {380.0f, 538.0f, 700.0f}) {
    const double c = std::cosh(0.0072 * (lambda - 538.0));
    EXPECT_NEAR(visibleWavelengthPdf(lambda), 0.0039398 / (c * c), 2e-7);
  }
  double integral = 0;
  for (int i = 0; i < 47000; ++i) integral += visibleWavelengthPdf(360.0f + (i + 0.5f) * 0.01f) * 0.01;
  EXPECT_NEAR(integral, 1.0, 1e-5);
  EXPECT_EQ(visibleWavelengthPdf(359.0f), 0.0f);
  // The inverse CDF is the published closed form and inverts the CDF.
  for (float u : {0.0f, 0.1f, 0.5f, 0.9f, 0.999f}) {
    const float lambda = sampleVisibleWavelength(u);
    EXPECT_NEAR(lambda, 538.0 - 138.889 * std::atanh(0.85691 - 1.82750 * u), 0.05);
    EXPECT_NEAR(visibleWavelengthCdf(lambda), u, 1e-5);
  }
  EXPECT_NEAR(sampleVisibleWavelength(0.0f), 360.0f, 1e-3);
  EXPECT_LT(sampleVisibleWavelength(std::nextafter(1.0f, 0.0f)), 830.0f);
}

TEST(Wavelengths, ChiSquareOfSampledWavelengthsAgainstTheDensity) {
  // 20 equal-probability bins via the CDF would be circular; use equal-width 23.5 nm bins and
  // integrate the density numerically for the expected counts. Samples come from a simple
  // 64-bit LCG stream (independent of the samplers under test elsewhere).
  const int bins = 20, n = 200000;
  std::vector<double> observed(bins, 0.0);
  uint64_t state = 12345;
  for (int i = 0; i < n; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const float u = float(state >> 40) * 0x1p-24f;
    const float lambda = sampleVisibleWavelength(u);
    int b = int((lambda - 360.0f) / 23.5f);
    observed[std::min(b, bins - 1)] += 1;
  }
  double chi2 = 0;
  for (int b = 0; b < bins; ++b) {
    double p = 0;
    for (int k = 0; k < 2350; ++k) p += visibleWavelengthPdf(360.0f + 23.5f * b + (k + 0.5f) * 0.01f) * 0.01;
    const double expected = p * n;
    chi2 += (observed[b] - expected) * (observed[b] - expected) / expected;
  }
  // 19 degrees of freedom: the 0.999 quantile is 43.8.
  EXPECT_LT(chi2, 43.8);
}

TEST(Wavelengths, GroupEstimatorIsUnbiasedForAFlatSpectrum) {
  for (int count : {1, 4, 8}) {
    double x = 0, y = 0, z = 0;
    const int n = 4096;
    for (int i = 0; i < n; ++i) {
      const WavelengthGroup group = sampleWavelengthGroup((i + 0.5f) / n, count);
      float ones[kMaxWavelengths] = {1, 1, 1, 1, 1, 1, 1, 1};
      const Xyz c = radianceGroupToXyz(group, ones);
      x += c.x, y += c.y, z += c.z;
    }
    EXPECT_NEAR(y / n, 1.0, 2e-3) << count;
    EXPECT_NEAR(x / n, 1.0, 3e-3) << count;
    EXPECT_NEAR(z / n, 1.0, 3e-3) << count;
  }
  // The group's wavelengths are rotated evenly in the primary sample space.
  const WavelengthGroup g = sampleWavelengthGroup(0.1f, 4);
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(visibleWavelengthCdf(g.lambdaNm[j]), std::fmod(0.1f + 0.25f * j, 1.0f), 1e-5);
}

// sampleWavelengthGroupStratified: the group as a set depends on uSet alone, the hero is any of
// its lanes with equal probability and has the visible density, and stratified uSet values
// stratify the lanes at count times their number (the point of the construction).
TEST(WavelengthSampling, StratifiedGroupsKeepTheSetStratifyTheLanesAndLeaveTheHeroUniform) {
  for (const int count : {4, 8}) {
    // The set: lane j of the rotation (uSet + j) / count, the hero picked by uHero.
    for (const float uHero : {0.0f, 0.3f, 0.99999f}) {
      const WavelengthGroup g = sampleWavelengthGroupStratified(0.37f, uHero, count);
      std::vector<float> cdfs;
      for (int j = 0; j < count; ++j) cdfs.push_back(visibleWavelengthCdf(g.lambdaNm[size_t(j)]));
      EXPECT_NEAR(cdfs[0], (0.37f + std::floor(uHero * count)) / count, 2e-5) << count << " " << uHero;
      std::sort(cdfs.begin(), cdfs.end());
      for (int j = 0; j < count; ++j) EXPECT_NEAR(cdfs[size_t(j)], (0.37f + j) / count, 2e-5) << count << " " << j;
    }
    // Stratified: 16 samples with one uSet per 1/16 give 16 x count lanes, one per CDF
    // stratum of width 1 / (16 count). (Rotating u_j = frac(u + j / count) by the same u would
    // leave the lanes' offsets within each 1/count of the CDF only 16 / count-fold stratified.)
    sampling::Pcg32 rng(3, 5);
    std::vector<int> perStratum(size_t(16 * count), 0);
    for (int i = 0; i < 16; ++i) {
      const WavelengthGroup g = sampleWavelengthGroupStratified((i + rng.nextFloat()) / 16.0f, rng.nextFloat(), count);
      for (int j = 0; j < count; ++j)
        ++perStratum[size_t(std::min(int(visibleWavelengthCdf(g.lambdaNm[size_t(j)]) * 16 * count), 16 * count - 1))];
    }
    EXPECT_EQ(*std::min_element(perStratum.begin(), perStratum.end()), 1) << count;
    EXPECT_EQ(*std::max_element(perStratum.begin(), perStratum.end()), 1) << count;
    // The hero's CDF value is uniform for independent uniform uSet and uHero (chi-square over
    // 64 cells, 1M samples), so its wavelength has the visible density.
    const int kSamples = 1 << 20, kCells = 64;
    std::vector<double> observed(kCells, 0.0), expected(kCells, double(kSamples) / kCells);
    for (int i = 0; i < kSamples; ++i) {
      const WavelengthGroup g = sampleWavelengthGroupStratified(rng.nextFloat(), rng.nextFloat(), count);
      observed[size_t(std::min(int(visibleWavelengthCdf(g.lambdaNm[0]) * kCells), kCells - 1))] += 1;
    }
    const test::ChiSquareResult r = test::chiSquareTest(observed, expected, 0.01, 2);
    EXPECT_TRUE(r.passed) << count << ": " << r.detail;
  }
}

}  // namespace
}  // namespace tex::color
