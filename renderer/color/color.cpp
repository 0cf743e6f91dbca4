#include "renderer/color/color.h"

#include <cmath>

#include "renderer/color/cie_tables.h"

namespace tex::color {

Xyz cieXyzBar(float lambdaNm) {
  const float t = lambdaNm - float(kCieLambdaMinNm);
  if (!(t >= 0.0f) || t > float(kCieSampleCount - 1)) return {};
  int i = int(t);
  if (i >= kCieSampleCount - 1) i = kCieSampleCount - 2;
  const float f = t - float(i);
  return {kCie1931X[i] + f * (kCie1931X[i + 1] - kCie1931X[i]),
          kCie1931Y[i] + f * (kCie1931Y[i + 1] - kCie1931Y[i]),
          kCie1931Z[i] + f * (kCie1931Z[i + 1] - kCie1931Z[i])};
}

float d65RelativePower(float lambdaNm) {
  const float t = (lambdaNm - float(kD65LambdaMinNm)) / float(kD65LambdaStepNm);
  if (!(t >= 0.0f) || t > float(kD65SampleCount - 1)) return 0.0f;
  int i = int(t);
  if (i >= kD65SampleCount - 1) i = kD65SampleCount - 2;
  const float f = t - float(i);
  return kD65[i] + f * (kD65[i + 1] - kD65[i]);
}

Rgb xyzToLinearSrgb(const Xyz& c) {
  return {3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z,
          -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
          0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z};
}

Xyz linearSrgbToXyz(const Rgb& c) {
  return {0.4124564f * c.r + 0.3575761f * c.g + 0.1804375f * c.b,
          0.2126729f * c.r + 0.7151522f * c.g + 0.0721750f * c.b,
          0.0193339f * c.r + 0.1191920f * c.g + 0.9503041f * c.b};
}

}  // namespace tex::color
