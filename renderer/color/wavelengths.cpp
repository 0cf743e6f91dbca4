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
    group.lambdaNm[j] = sampleVisibleWavelength(uj);
    group.pdfLambda[j] = visibleWavelengthPdf(group.lambdaNm[j]);
  }
  return group;
}

}  // namespace tex::color
