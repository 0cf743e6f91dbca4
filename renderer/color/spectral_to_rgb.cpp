#include "renderer/color/spectral_to_rgb.h"

#include "renderer/color/cie_tables.h"

namespace tex::color {

namespace {

// Integral of y-bar * D65 over 360..830 nm (1 nm steps), computed once from the tables.
double d65YIntegral() {
  static const double value = [] {
    double sum = 0.0;
    for (int i = 0; i < kCieSampleCount; ++i) {
      sum += double(kCie1931Y[i]) * d65RelativePower(float(kCieLambdaMinNm + i));
    }
    return sum;
  }();
  return value;
}

}  // namespace

Xyz radianceGroupToXyz(const WavelengthGroup& group, const float* radiance) {
  float weights[kMaxWavelengths];
  for (int j = 0; j < group.count; ++j) {
    weights[j] = group.pdfLambda[j] > 0.0f ? radiance[j] / group.pdfLambda[j] : 0.0f;
  }
  return xyzFromRadianceOverPdf(group.lambdaNm.data(), weights, group.count);
}

Rgb radianceGroupToLinearSrgb(const WavelengthGroup& group, const float* radiance) {
  return xyzToLinearSrgb(radianceGroupToXyz(group, radiance));
}

Xyz reflectanceGroupToXyz(const WavelengthGroup& group, const float* reflectance) {
  float weights[kMaxWavelengths];
  const double scale = kCie1931YIntegralNm / d65YIntegral();
  for (int j = 0; j < group.count; ++j) {
    const float lit = reflectance[j] * d65RelativePower(group.lambdaNm[j]);
    weights[j] = group.pdfLambda[j] > 0.0f ? float(lit * scale / group.pdfLambda[j]) : 0.0f;
  }
  return xyzFromRadianceOverPdf(group.lambdaNm.data(), weights, group.count);
}

Rgb reflectanceGroupToLinearSrgb(const WavelengthGroup& group, const float* reflectance) {
  return xyzToLinearSrgb(reflectanceGroupToXyz(group, reflectance));
}

Xyz radianceSpectrumToXyz(const std::function<float(float)>& radiance) {
  double x = 0, y = 0, z = 0;
  for (int i = 0; i < kCieSampleCount; ++i) {
    const double l = radiance(float(kCieLambdaMinNm + i));
    x += kCie1931X[i] * l;
    y += kCie1931Y[i] * l;
    z += kCie1931Z[i] * l;
  }
  return {float(x / kCie1931YIntegralNm), float(y / kCie1931YIntegralNm), float(z / kCie1931YIntegralNm)};
}

Xyz reflectanceSpectrumToXyz(const std::function<float(float)>& reflectance) {
  double x = 0, y = 0, z = 0;
  for (int i = 0; i < kCieSampleCount; ++i) {
    const float lambda = float(kCieLambdaMinNm + i);
    const double l = double(reflectance(lambda)) * d65RelativePower(lambda);
    x += kCie1931X[i] * l;
    y += kCie1931Y[i] * l;
    z += kCie1931Z[i] * l;
  }
  const double n = d65YIntegral();
  return {float(x / n), float(y / n), float(z / n)};
}

}  // namespace tex::color
