#include "renderer/color/wavelengths.h"

#include <algorithm>
#include <cmath>

namespace tex::color {

namespace {
constexpr double kA = 0.0072;     // per nm
constexpr double kCentreNm = 538.0;
const double kTanhLow = std::tanh(kA * (kCentreNm - kVisibleLambdaMinNm));   // 0.85691
const double kTanhHigh = std::tanh(kA * (kVisibleLambdaMaxNm - kCentreNm));  // 0.97059
const double kTanhSpan = kTanhLow + kTanhHigh;                               // 1.82750
}  // namespace

float visibleWavelengthPdf(float lambdaNm) {
  if (!(lambdaNm >= kVisibleLambdaMinNm && lambdaNm <= kVisibleLambdaMaxNm)) return 0.0f;
  const double c = std::cosh(kA * (double(lambdaNm) - kCentreNm));
  return float(kA / (kTanhSpan * c * c));
}

float sampleVisibleWavelength(float u) {
  const double lambda = kCentreNm - std::atanh(kTanhLow - kTanhSpan * double(u)) / kA;
  // Rounding near u = 1 must not leave the range the pdf is defined on.
  return std::clamp(float(lambda), kVisibleLambdaMinNm, std::nextafter(kVisibleLambdaMaxNm, 0.0f));
}

float visibleWavelengthCdf(float lambdaNm) {
  if (lambdaNm <= kVisibleLambdaMinNm) return 0.0f;
  if (lambdaNm >= kVisibleLambdaMaxNm) return 1.0f;
  return float((kTanhLow + std::tanh(kA * (double(lambdaNm) - kCentreNm))) / kTanhSpan);
}

WavelengthGroup sampleWavelengthGroup(float u, int count) {
  WavelengthGroup group;
  group.count = std::clamp(count, 1, kMaxWavelengths);
  for (int j = 0; j < group.count; ++j) {
    float uj = u + float(j) / float(group.count);
    if (uj >= 1.0f) uj -= 1.0f;
    // With t = tanh(a (538 - lambda)) = A - (A + B) u, the density a / ((A + B) cosh^2) is
    // a (1 - t^2) / (A + B): no cosh needed (this runs for every path).
    const double t = kTanhLow - kTanhSpan * double(uj);
    const double lambda = kCentreNm - 0.5 * std::log((1.0 + t) / (1.0 - t)) / kA;
    group.lambdaNm[j] = std::clamp(float(lambda), kVisibleLambdaMinNm, std::nextafter(kVisibleLambdaMaxNm, 0.0f));
    group.pdfLambda[j] = group.lambdaNm[j] == float(lambda) ? float(kA / kTanhSpan * (1.0 - t * t))
                                                            : visibleWavelengthPdf(group.lambdaNm[j]);
  }
  return group;
}

}  // namespace tex::color
