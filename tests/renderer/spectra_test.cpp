// Spectra: the RGB-to-spectrum table (Jakob & Hanika 2019) and its uses, D65, blackbodies,
// SpectrumSource and the named-spectra library.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "renderer/color/spectral_to_rgb.h"
#include "renderer/sampling/pcg.h"
#include "renderer/spectra/rgb_spectrum.h"
#include "renderer/spectra/rgb_table.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {
namespace {

// Largest per-channel difference between an RGB and the linear sRGB of `reflectance` under D65.
template <class F>
float reflectanceRoundTripError(const Vec3& rgb, F&& reflectance) {
  const color::Rgb out = color::xyzToLinearSrgb(color::reflectanceSpectrumToXyz(reflectance));
  return std::max({std::abs(out.r - rgb.x), std::abs(out.g - rgb.y), std::abs(out.b - rgb.z)});
}

Vec3 randomRgb(sampling::Pcg32& rng) { return Vec3(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()); }

TEST(Spectra, ReflectanceRoundTripOnAGridOfTheRgbCube) {
  // 9^3 colours of [0,1]^3 upsampled and integrated under D65 come back to themselves.
  constexpr float kBound = 1e-3f;
  float maxError = 0, sumError = 0, maxBoxError = 0;
  int count = 0;
  for (int r = 0; r <= 8; ++r)
    for (int g = 0; g <= 8; ++g)
      for (int b = 0; b <= 8; ++b) {
        const Vec3 rgb(r / 8.0f, g / 8.0f, b / 8.0f);
        const SigmoidPolynomial s = rgbToSigmoid(rgb);
        const float error = reflectanceRoundTripError(rgb, [&](float l) { return s(l); });
        maxError = std::max(maxError, error);
        sumError += error;
        ++count;
        // A naive upsampler (three boxes blended by r, g, b) for scale: the bound must reject it.
        maxBoxError = std::max(maxBoxError, reflectanceRoundTripError(rgb, [&](float l) {
                                 return l < 490.0f ? rgb.z : (l < 590.0f ? rgb.y : rgb.x);
                               }));
      }
  std::printf("RGB round trip over 9^3 colours: max error %.3g, mean %.3g (box blend: max %.3g)\n",
              maxError, sumError / float(count), maxBoxError);
  EXPECT_LT(maxError, kBound);
  EXPECT_LT(sumError / float(count), 3e-4f);
  EXPECT_GT(maxBoxError, 10 * kBound);
}

TEST(Spectra, ReflectanceRoundTripForRandomColours) {
  // Off the grid (between table nodes, near white, near the cube's faces) the error stays small.
  sampling::Pcg32 rng(7, 1);
  float maxError = 0, sumError = 0;
  constexpr int kCount = 3000;
  for (int i = 0; i < kCount; ++i) {
    Vec3 rgb = randomRgb(rng);
    if (i % 3 == 0) rgb = Vec3(1.0f) - 0.05f * rgb;  // a third near white
    const SigmoidPolynomial s = rgbToSigmoid(rgb);
    const float error = reflectanceRoundTripError(rgb, [&](float l) { return s(l); });
    maxError = std::max(maxError, error);
    sumError += error;
  }
  std::printf("RGB round trip over %d random colours: max error %.3g, mean %.3g\n", kCount, maxError,
              sumError / kCount);
  EXPECT_LT(maxError, 2e-3f);
  EXPECT_LT(sumError / kCount, 4e-4f);
}

TEST(Spectra, GeneratorResidualsAtTheTableNodes) {
  // Every node's coefficients reproduce the node's colour (the fit itself, without
  // interpolation). Slice 0 (black) copies slice 1 and the white corner is asymptotic: skipped.
  const RgbSigmoidTable& table = rgbSigmoidTable();
  const int res = table.resolution;
  ASSERT_GE(res, 16);
  float maxError = 0;
  for (int l = 0; l < 3; ++l)
    for (int k = 1; k < res; k += 3)
      for (int j = 0; j < res; j += 3)
        for (int i = 0; i < res; i += 3) {
          const float* c = table.cell(l, k, j, i);
          const SigmoidPolynomial s{c[0], c[1], c[2]};
          const float z = table.zNodes[k];
          float rgb[3];
          rgb[l] = z;
          rgb[(l + 1) % 3] = table.xyNodes[i] * z;
          rgb[(l + 2) % 3] = table.xyNodes[j] * z;
          const Vec3 target(rgb[0], rgb[1], rgb[2]);
          maxError = std::max(maxError, reflectanceRoundTripError(target, [&](float lambda) { return s(lambda); }));
        }
  std::printf("table nodes: max round-trip error %.3g\n", maxError);
  EXPECT_LT(maxError, 3e-5f);
}

TEST(Spectra, BlackAndWhiteAreExactlyZeroAndOne) {
  const Wavelengths lambda = color::sampleWavelengthGroup(0.3f, 8);
  const Spectrum black = rgbReflectanceSpectrum(Vec3(0.0f), lambda);
  const Spectrum white = rgbReflectanceSpectrum(Vec3(1.0f), lambda);
  for (int i = 0; i < lambda.count; ++i) {
    EXPECT_EQ(black[i], 0.0f);
    EXPECT_EQ(white[i], 1.0f);
  }
  for (float l = 360.0f; l <= 830.0f; l += 10.0f) {
    EXPECT_EQ(rgbReflectanceAt(Vec3(0.0f), l), 0.0f);
    EXPECT_EQ(rgbReflectanceAt(Vec3(1.0f), l), 1.0f);
    EXPECT_NEAR(rgbReflectanceAt(Vec3(0.25f), l), 0.25f, 1e-6f);  // greys are flat
  }
  // Out-of-range and NaN inputs clamp instead of producing NaN.
  EXPECT_EQ(rgbReflectanceAt(Vec3(2.0f, 3.0f, 5.0f), 550.0f), 1.0f);
  EXPECT_EQ(rgbReflectanceAt(Vec3(-1.0f, NAN, -2.0f), 550.0f), 0.0f);
}

TEST(Spectra, ReflectancesStayInTheUnitInterval) {
  sampling::Pcg32 rng(11, 1);
  for (int i = 0; i < 2000; ++i) {
    Vec3 rgb = randomRgb(rng);
    if (i % 4 == 0) rgb[i % 3] = 1.0f;  // faces of the cube: the most saturated colours
    if (i % 4 == 1) rgb[i % 3] = 0.0f;
    const SigmoidPolynomial s = rgbToSigmoid(rgb);
    float sampledMax = 0;
    for (float l = 360.0f; l <= 830.0f; l += 2.0f) {
      const float v = s(l);
      ASSERT_GE(v, 0.0f) << rgb.x << " " << rgb.y << " " << rgb.z << " at " << l;
      ASSERT_LE(v, 1.0f) << rgb.x << " " << rgb.y << " " << rgb.z << " at " << l;
      sampledMax = std::max(sampledMax, v);
    }
    EXPECT_LE(s.maxValue(), 1.0f);
    EXPECT_GE(s.maxValue(), sampledMax - 1e-5f);  // maxValue bounds every sample (to float rounding)
    EXPECT_LT(s.maxValue(), sampledMax + 1e-3f);  // and is tight
  }
}

TEST(Spectra, SpectraAreSmoothInWavelengthAndContinuousInRgb) {
  sampling::Pcg32 rng(5, 1);
  float maxStepPerNm = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 rgb = randomRgb(rng);
    const SigmoidPolynomial s = rgbToSigmoid(rgb);
    for (float l = 360.0f; l < 830.0f; l += 1.0f) maxStepPerNm = std::max(maxStepPerNm, std::abs(s(l + 1.0f) - s(l)));
  }
  EXPECT_LT(maxStepPerNm, 0.1f);  // the steepest fits (saturated colours) rise by ~0.06 / nm

  // Continuity across the 3 regions (largest component changes) and across cells: a tiny
  // RGB step changes the spectrum a little.
  const auto maxDifference = [](const Vec3& a, const Vec3& b) {
    const SigmoidPolynomial sa = rgbToSigmoid(a), sb = rgbToSigmoid(b);
    float d = 0;
    for (float l = 360.0f; l <= 830.0f; l += 5.0f) d = std::max(d, std::abs(sa(l) - sb(l)));
    return d;
  };
  constexpr float kStep = 1e-4f;
  for (int i = 0; i < 500; ++i) {
    const Vec3 rgb = randomRgb(rng);
    // Region boundary: equal largest components, nudged either way.
    const float top = std::max({rgb.x, rgb.y, rgb.z});
    const Vec3 tie(top, top, rgb.z * 0.9f);
    EXPECT_LT(maxDifference(tie + Vec3(kStep, 0, 0), tie + Vec3(0, kStep, 0)), 0.02f)
        << tie.x << " " << tie.y << " " << tie.z;
    const Vec3 step(kStep * (rng.nextFloat() - 0.5f), kStep * (rng.nextFloat() - 0.5f), kStep * (rng.nextFloat() - 0.5f));
    EXPECT_LT(maxDifference(rgb, rgb + step), 0.02f) << rgb.x << " " << rgb.y << " " << rgb.z;
  }
}

TEST(Spectra, UnboundedAndIlluminantDevelopToTheirRgb) {
  // Unbounded: as a reflectance under D65 (values above 1 allowed), the colour comes back.
  for (const Vec3& rgb : {Vec3(2.0f, 4.0f, 1.0f), Vec3(0.3f, 0.1f, 0.05f), Vec3(10.0f, 10.0f, 10.0f)}) {
    const float scale = std::max({rgb.x, rgb.y, rgb.z});
    EXPECT_LT(reflectanceRoundTripError(rgb, [&](float l) { return rgbUnboundedAt(rgb, l); }), 1e-3f * scale);
  }
  // Illuminant white: luminance 1 and linear sRGB (1,1,1).
  const color::Xyz whiteXyz = color::radianceSpectrumToXyz([](float l) { return rgbIlluminantAt(Vec3(1.0f), l); });
  EXPECT_NEAR(whiteXyz.y, 1.0f, 1e-4f);
  const color::Rgb white = color::xyzToLinearSrgb(whiteXyz);
  EXPECT_NEAR(white.r, 1.0f, 1e-3f);
  EXPECT_NEAR(white.g, 1.0f, 1e-3f);
  EXPECT_NEAR(white.b, 1.0f, 1e-3f);
  // A coloured, bright illuminant develops to its RGB too.
  const Vec3 warm(3.0f, 2.0f, 0.5f);
  const color::Rgb out = color::xyzToLinearSrgb(color::radianceSpectrumToXyz([&](float l) { return rgbIlluminantAt(warm, l); }));
  EXPECT_NEAR(out.r, warm.x, 3e-3f);
  EXPECT_NEAR(out.g, warm.y, 3e-3f);
  EXPECT_NEAR(out.b, warm.z, 3e-3f);
  // The group versions agree with the scalar ones.
  const Wavelengths lambda = color::sampleWavelengthGroup(0.71f, 4);
  const Spectrum illum = rgbIlluminantSpectrum(warm, lambda), unb = rgbUnboundedSpectrum(warm, lambda);
  for (int i = 0; i < lambda.count; ++i) {
    EXPECT_FLOAT_EQ(illum[i], rgbIlluminantAt(warm, lambda.lambdaNm[i]));
    EXPECT_FLOAT_EQ(unb[i], rgbUnboundedAt(warm, lambda.lambdaNm[i]));
  }
  for (int i = lambda.count; i < kLanes; ++i) EXPECT_EQ(illum[i], 0.0f);
  EXPECT_EQ(rgbIlluminantAt(Vec3(0.0f), 550.0f), 0.0f);
}

TEST(Spectra, D65NormalisedHasUnitLuminance) {
  const color::Xyz xyz = color::radianceSpectrumToXyz(d65Normalised);
  EXPECT_NEAR(xyz.y, 1.0f, 1e-5f);
  // Shape of the CIE table: 100 at 560 nm relative to its value at 460 nm (117.812).
  EXPECT_NEAR(d65Normalised(460.0f) / d65Normalised(560.0f), 1.17812f, 1e-4f);
}

TEST(Spectra, BlackbodyPeaksAtWiensWavelength) {
  for (float kelvin : {2700.0f, 4000.0f, 5500.0f, 6500.0f}) {
    const float wienNm = 2.897771955e6f / kelvin;
    float bestNm = 0, best = 0;
    for (float l = 300.0f; l <= 1200.0f; l += 0.1f) {
      const float v = blackbodyNormalised(l, kelvin);
      if (v > best) best = v, bestNm = l;
    }
    EXPECT_NEAR(bestNm, wienNm, 0.2f) << kelvin;
    EXPECT_NEAR(best, 1.0f, 1e-5f);
    // Planck's ratio between two wavelengths, written out independently.
    const auto planck = [&](double nm) {
      const double m = nm * 1e-9;
      return 1.0 / (std::pow(m, 5) * (std::exp(6.62607015e-34 * 299792458.0 / (m * 1.380649e-23 * kelvin)) - 1.0));
    };
    EXPECT_NEAR(blackbodyNormalised(450.0f, kelvin) / blackbodyNormalised(650.0f, kelvin), planck(450) / planck(650),
                1e-4 * planck(450) / planck(650));
  }
  EXPECT_EQ(blackbodyNormalised(550.0f, 0.0f), 0.0f);
}

TEST(Spectra, NamedSpectraLoadAndInterpolate) {
  const std::vector<std::string> names = namedSpectrumNames();
  for (const char* required : {"cornell-white", "cornell-green", "cornell-red", "cornell-light", "Au-eta", "Au-k",
                               "Ag-eta", "Ag-k", "Cu-eta", "Cu-k", "Al-eta", "Al-k", "D65", "illuminant-A", "BK7-ior"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
  for (const std::string& name : names) {
    const auto* table = namedSpectrum(name);
    ASSERT_NE(table, nullptr) << name;
    ASSERT_GE(table->size(), 2u) << name;
    for (size_t i = 1; i < table->size(); ++i) EXPECT_LT((*table)[i - 1].first, (*table)[i].first) << name;
    for (const auto& [lambda, value] : *table) EXPECT_TRUE(std::isfinite(value) && value >= 0.0f) << name << " " << lambda;
  }
  EXPECT_EQ(namedSpectrum("no-such-spectrum"), nullptr);

  const auto& light = *namedSpectrum("cornell-light");
  EXPECT_FLOAT_EQ(interpolateTable(light, 500.0f), 8.0f);
  EXPECT_FLOAT_EQ(interpolateTable(light, 550.0f), 11.8f);  // halfway between 8 and 15.6
  EXPECT_FLOAT_EQ(interpolateTable(light, 700.0f), 18.4f);
  EXPECT_EQ(interpolateTable(light, 399.0f), 0.0f);
  EXPECT_EQ(interpolateTable(light, 701.0f), 0.0f);

  // D65 and illuminant A from the library have luminance 1; A is the reddish one.
  for (const char* name : {"D65", "illuminant-A"}) {
    const auto& t = *namedSpectrum(name);
    EXPECT_NEAR(color::radianceSpectrumToXyz([&](float l) { return interpolateTable(t, l); }).y, 1.0f, 1e-4f) << name;
  }
  const auto& a = *namedSpectrum("illuminant-A");
  EXPECT_GT(interpolateTable(a, 650.0f), 2.0f * interpolateTable(a, 450.0f));
  // Illuminant A's defining formula: S(560) = 100, S(400) = 14.708 (CIE 15:2004 table), ratio.
  EXPECT_NEAR(interpolateTable(a, 400.0f) / interpolateTable(a, 560.0f), 0.14708f, 2e-4f);

  // Glasses: BK7's n_d (587.6 nm) is 1.5168 (SCHOTT), fused silica's 1.4585 (Malitson).
  EXPECT_NEAR(interpolateTable(*namedSpectrum("BK7-ior"), 587.56f), 1.5168f, 2e-4f);
  EXPECT_NEAR(interpolateTable(*namedSpectrum("fused-silica-ior"), 587.56f), 1.4585f, 2e-4f);
}

TEST(Spectra, CornellBoxWallsHaveTheirPublishedColours) {
  const auto& white = *namedSpectrum("cornell-white");
  EXPECT_EQ(white.size(), 76u);
  EXPECT_FLOAT_EQ(interpolateTable(white, 400.0f), 0.343f);
  float mean = 0;
  for (float l = 450.0f; l <= 650.0f; l += 1.0f) mean += interpolateTable(white, l) / 201.0f;
  EXPECT_NEAR(mean, 0.74f, 0.02f);
  EXPECT_NEAR(interpolateTable(white, 550.0f), 0.74f, 0.03f);
  const auto colourOf = [](const char* name) {
    const auto& t = *namedSpectrum(name);
    return color::xyzToLinearSrgb(color::reflectanceSpectrumToXyz([&](float l) { return interpolateTable(t, l); }));
  };
  const color::Rgb red = colourOf("cornell-red"), green = colourOf("cornell-green");
  EXPECT_GT(red.r, 3.0f * red.g);
  EXPECT_GT(red.r, 3.0f * red.b);
  EXPECT_GT(green.g, 2.0f * green.r);
  EXPECT_GT(green.g, 2.0f * green.b);
}

TEST(Spectra, MetalsAtNormalIncidenceHaveTheirColours) {
  // Fresnel reflectance of a conductor at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
  const auto colourOf = [](const std::string& metal) {
    const auto& eta = *namedSpectrum(metal + "-eta");
    const auto& k = *namedSpectrum(metal + "-k");
    return color::xyzToLinearSrgb(color::reflectanceSpectrumToXyz([&](float l) {
      const float n = interpolateTable(eta, l), kk = interpolateTable(k, l);
      return ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk);
    }));
  };
  const color::Rgb gold = colourOf("Au"), copper = colourOf("Cu"), silver = colourOf("Ag"), aluminium = colourOf("Al");
  EXPECT_GT(gold.r, 1.5f * gold.b);  // yellow
  EXPECT_GT(gold.g, gold.b);
  EXPECT_GT(copper.r, copper.g);  // reddish
  EXPECT_GT(copper.g, copper.b);
  for (const color::Rgb& c : {silver, aluminium}) {  // bright and nearly neutral
    EXPECT_GT(std::min({c.r, c.g, c.b}), 0.85f);
    EXPECT_LT(std::max({c.r, c.g, c.b}) / std::min({c.r, c.g, c.b}), 1.1f);
  }
}

TEST(Spectra, SpectrumSourceEvaluatesEveryKind) {
  const Wavelengths lambda = color::sampleWavelengthGroup(0.42f, 8);
  const auto expectSampleMatchesAt = [&](const SpectrumSource& s) {
    const Spectrum v = s.sample(lambda);
    for (int i = 0; i < lambda.count; ++i) EXPECT_FLOAT_EQ(v[i], s.at(lambda.lambdaNm[i]));
  };

  SpectrumDesc desc;
  EXPECT_EQ(SpectrumSource().at(550.0f), 0.0f);
  const SpectrumSource c = SpectrumSource::constant(0.4f);
  EXPECT_FLOAT_EQ(c.at(450.0f), 0.4f);
  EXPECT_TRUE(c.isConstant());
  EXPECT_FLOAT_EQ(c.luminance(), 0.4f);
  expectSampleMatchesAt(c);

  desc.kind = SpectrumDesc::Kind::Rgb;
  desc.rgb = Vec3(0.8f, 0.3f, 0.1f);
  desc.scale = 0.5f;
  const SpectrumSource refl(desc, SpectrumUse::Reflectance);
  EXPECT_FLOAT_EQ(refl.at(600.0f), 0.5f * rgbReflectanceAt(desc.rgb, 600.0f));
  EXPECT_FALSE(refl.isConstant());
  // Luminance of a reflectance: Y under D65 of the upsampled colour (times the scale).
  const float yOfRgb = 0.2126729f * desc.rgb.x + 0.7151522f * desc.rgb.y + 0.0721750f * desc.rgb.z;
  EXPECT_NEAR(refl.luminance(), 0.5f * yOfRgb, 1e-3f);
  expectSampleMatchesAt(refl);

  desc.rgb = Vec3(4.0f, 2.0f, 1.0f);
  desc.scale = 2.0f;
  const SpectrumSource light(desc, SpectrumUse::Illuminant);
  EXPECT_FLOAT_EQ(light.at(520.0f), 2.0f * rgbIlluminantAt(desc.rgb, 520.0f));
  EXPECT_NEAR(light.luminance(), 2.0f * (0.2126729f * 4 + 0.7151522f * 2 + 0.0721750f), 5e-3f);
  expectSampleMatchesAt(light);
  const SpectrumSource unbounded(desc, SpectrumUse::Unbounded);
  EXPECT_FLOAT_EQ(unbounded.at(520.0f), 2.0f * rgbUnboundedAt(desc.rgb, 520.0f));

  desc.rgb = Vec3(0.6f);
  EXPECT_TRUE(SpectrumSource(desc, SpectrumUse::Reflectance).isConstant());
  EXPECT_FALSE(SpectrumSource(desc, SpectrumUse::Illuminant).isConstant());  // D65-shaped

  desc = SpectrumDesc();
  desc.kind = SpectrumDesc::Kind::Blackbody;
  desc.kelvin = 3000.0f;
  desc.scale = 3.0f;
  const SpectrumSource bb(desc, SpectrumUse::Illuminant);
  EXPECT_FLOAT_EQ(bb.at(700.0f), 3.0f * blackbodyNormalised(700.0f, 3000.0f));
  expectSampleMatchesAt(bb);

  desc = SpectrumDesc();
  desc.kind = SpectrumDesc::Kind::Named;
  desc.name = "cornell-light";
  desc.scale = 0.5f;
  const SpectrumSource named(desc, SpectrumUse::Illuminant);
  EXPECT_FLOAT_EQ(named.at(600.0f), 7.8f);
  expectSampleMatchesAt(named);
  desc.name = "no-such-spectrum";
  EXPECT_THROW(SpectrumSource(desc, SpectrumUse::Reflectance), std::invalid_argument);

  desc = SpectrumDesc();
  desc.kind = SpectrumDesc::Kind::Tabulated;
  desc.lambdaNm = {400.0f, 500.0f, 700.0f};
  desc.values = {0.2f, 0.6f, 0.2f};
  const SpectrumSource tab(desc, SpectrumUse::Reflectance);
  EXPECT_FLOAT_EQ(tab.at(450.0f), 0.4f);
  EXPECT_FLOAT_EQ(tab.at(600.0f), 0.4f);
  EXPECT_EQ(tab.at(390.0f), 0.0f);
  const SpectrumSource tabCopy = tab;  // copies share the table
  EXPECT_FLOAT_EQ(tabCopy.at(500.0f), 0.6f);
  expectSampleMatchesAt(tab);
  desc.values = {0.2f, 0.6f};
  EXPECT_THROW(SpectrumSource(desc, SpectrumUse::Reflectance), std::invalid_argument);
  desc.values = {0.2f, 0.6f, 0.2f};
  desc.lambdaNm = {400.0f, 400.0f, 700.0f};
  EXPECT_THROW(SpectrumSource(desc, SpectrumUse::Reflectance), std::invalid_argument);
}

// Tables whose knots fall between whole nanometres are evaluated exactly: resampled at whole
// nanometres, a line 1 nm wide centred on 550 had rendered at twice its energy and one centred
// on 550.5 had vanished (and with luminance 0 a light of it would never be chosen).
TEST(Spectra, NarrowLinesBetweenWholeNanometresKeepTheirShapeAndEnergy) {
  struct Case {
    float a, peak, b, luminance;  // luminance: 1000 x (b - a) / 2 x ybar(peak) / 106.857
  };
  for (const Case c : {Case{549.5f, 550.0f, 550.5f, 4.655f}, Case{550.2f, 550.5f, 550.8f, 2.796f}}) {
    SpectrumDesc desc;
    desc.kind = SpectrumDesc::Kind::Tabulated;
    desc.lambdaNm = {c.a, c.peak, c.b};
    desc.values = {0.0f, 1000.0f, 0.0f};
    const SpectrumSource line(desc, SpectrumUse::Illuminant);
    EXPECT_FLOAT_EQ(line.at(c.peak), 1000.0f);
    EXPECT_NEAR(line.at(0.5f * (c.a + c.peak)), 500.0f, 0.5f);  // float wavelengths near 550: 6e-5 nm apart
    EXPECT_EQ(line.at(c.b + 0.1f), 0.0f);
    EXPECT_NEAR(line.luminance(), c.luminance, 0.01f * c.luminance) << c.peak;
  }
}

}  // namespace
}  // namespace tex::render
