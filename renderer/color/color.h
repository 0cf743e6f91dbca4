// Colour spaces: CIE XYZ (1931 2-degree observer) and linear sRGB (ITU-R BT.709 primaries,
// D65 white). Plain values; no spectral sampling here (see wavelengths.h, spectral_to_rgb.h).
#pragma once

#include "renderer/color/cie_tables.h"

namespace tex::color {

struct Xyz {
  float x = 0, y = 0, z = 0;
};

struct Rgb {
  float r = 0, g = 0, b = 0;
};

// The three below are inline: every film record and every emission evaluation calls them
// per wavelength, and as calls they cost more than their arithmetic (and passed their
// results through the stack).

// Colour-matching functions at lambdaNm (linear interpolation of the 1 nm table; zero
// outside 360..830 nm).
inline Xyz cieXyzBar(float lambdaNm) {
  const float t = lambdaNm - float(kCieLambdaMinNm);
  if (!(t >= 0.0f) || t > float(kCieSampleCount - 1)) return {};
  int i = int(t);
  if (i >= kCieSampleCount - 1) i = kCieSampleCount - 2;
  const float f = t - float(i);
  return {kCie1931X[i] + f * (kCie1931X[i + 1] - kCie1931X[i]),
          kCie1931Y[i] + f * (kCie1931Y[i + 1] - kCie1931Y[i]),
          kCie1931Z[i] + f * (kCie1931Z[i + 1] - kCie1931Z[i])};
}

// D65 relative spectral power at lambdaNm (linear interpolation of the 5 nm table; zero
// outside 300..780 nm).
inline float d65RelativePower(float lambdaNm) {
  const float t = (lambdaNm - float(kD65LambdaMinNm)) / float(kD65LambdaStepNm);
  if (!(t >= 0.0f) || t > float(kD65SampleCount - 1)) return 0.0f;
  int i = int(t);
  if (i >= kD65SampleCount - 1) i = kD65SampleCount - 2;
  const float f = t - float(i);
  return kD65[i] + f * (kD65[i + 1] - kD65[i]);
}

// XYZ to linear sRGB and back (IEC 61966-2-1 matrix, D65 white: XYZ (0.9505, 1, 1.089) maps
// to RGB (1, 1, 1)).
inline Rgb xyzToLinearSrgb(const Xyz& c) {
  return {3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z,
          -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
          0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z};
}
Xyz linearSrgbToXyz(const Rgb& rgb);

}  // namespace tex::color
