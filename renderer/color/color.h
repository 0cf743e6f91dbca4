// Colour spaces: CIE XYZ (1931 2-degree observer) and linear sRGB (ITU-R BT.709 primaries,
// D65 white). Plain values; no spectral sampling here (see wavelengths.h, spectral_to_rgb.h).
#pragma once

namespace tex::color {

struct Xyz {
  float x = 0, y = 0, z = 0;
};

struct Rgb {
  float r = 0, g = 0, b = 0;
};

// Colour-matching functions at lambdaNm (linear interpolation of the 1 nm table; zero
// outside 360..830 nm).
Xyz cieXyzBar(float lambdaNm);

// D65 relative spectral power at lambdaNm (linear interpolation of the 5 nm table; zero
// outside 300..780 nm).
float d65RelativePower(float lambdaNm);

// XYZ to linear sRGB and back (IEC 61966-2-1 matrix, D65 white: XYZ (0.9505, 1, 1.089) maps
// to RGB (1, 1, 1)).
Rgb xyzToLinearSrgb(const Xyz& xyz);
Xyz linearSrgbToXyz(const Rgb& rgb);

}  // namespace tex::color
