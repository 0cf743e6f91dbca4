// From spectral samples to colour. A path carries a group of n wavelengths lambda_j drawn with
// marginal densities pdf_j (wavelengths.h); the Monte Carlo estimate of the tristimulus value
// of a spectral radiance L is
//   XYZ = 1 / (n * Ybar) * sum_j cmf(lambda_j) L(lambda_j) / pdf_j,   Ybar = integral of y-bar,
// normalised so that an equal-energy spectrum L = 1 has Y = 1. Reflectances are viewed under
// D65 instead, normalised so that R = 1 has Y = 1 and maps to sRGB (1, 1, 1).
#pragma once
#include <array>
#include <cstddef>
#include <functional>

#include "renderer/color/cie_tables.h"
#include "renderer/color/color.h"
#include "renderer/color/wavelengths.h"

namespace tex::color {

// 1 / (count Ybar), the estimate's normalisation: from a table for the group sizes paths carry
// (constant-folded, so the same double as the division, which cost a divsd per record).
inline double xyzEstimateScale(int count) {
  static constexpr auto kScale = [] {
    std::array<double, kMaxWavelengths + 1> scale{};
    for (int n = 1; n <= kMaxWavelengths; ++n) scale[size_t(n)] = 1.0 / (double(n) * kCie1931YIntegralNm);
    return scale;
  }();
  if (count >= 0 && count <= kMaxWavelengths) return kScale[size_t(count)];
  return count > 0 ? 1.0 / (double(count) * kCie1931YIntegralNm) : 0.0;
}

// Estimate from weights already divided by their pdfs: weightOverPdf[j] = L(lambda_j) / pdf_j.
// This is the form sample records store (see renderer/film/sample_record.h). Inline: the film
// calls it for every record.
inline Xyz xyzFromRadianceOverPdf(const float* lambdaNm, const float* radianceOverPdf, int count) {
  double x = 0, y = 0, z = 0;
  for (int j = 0; j < count; ++j) {
    const Xyz bar = cieXyzBar(lambdaNm[j]);
    x += double(bar.x) * radianceOverPdf[j];
    y += double(bar.y) * radianceOverPdf[j];
    z += double(bar.z) * radianceOverPdf[j];
  }
  const double scale = xyzEstimateScale(count);
  return {float(x * scale), float(y * scale), float(z * scale)};
}

// Radiance values at the group's wavelengths, with the group's pdfs.
Xyz radianceGroupToXyz(const WavelengthGroup& group, const float* radiance);
Rgb radianceGroupToLinearSrgb(const WavelengthGroup& group, const float* radiance);

// Reflectance values at the group's wavelengths, seen under D65.
Xyz reflectanceGroupToXyz(const WavelengthGroup& group, const float* reflectance);
Rgb reflectanceGroupToLinearSrgb(const WavelengthGroup& group, const float* reflectance);

// Deterministic quadrature (1 nm steps over 360..830 nm) of a full spectrum, for reference
// values and for evaluating a spectrum without noise.
Xyz radianceSpectrumToXyz(const std::function<float(float lambdaNm)>& radiance);
Xyz reflectanceSpectrumToXyz(const std::function<float(float lambdaNm)>& reflectance);

}  // namespace tex::color
