// RGB to spectrum: Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient
// Spectral Upsampling". A linear sRGB colour in [0,1]^3 maps to a smooth reflectance
// s(lambda) = sigmoid(c0 lambda^2 + c1 lambda + c2), sigmoid(x) = 1/2 + x / (2 sqrt(1 + x^2)),
// whose colour under D65 is the input. The coefficients come from a table over the RGB cube
// computed by our own optimiser (renderer/spectra/generate_rgb_table.cpp, see its header).
#pragma once
#include "renderer/core/geometry.h"
#include "renderer/core/spectrum.h"

namespace tex::render {

struct SigmoidPolynomial {
  float c0 = 0, c1 = 0, c2 = 0;  // in terms of lambda in nm
  float operator()(float lambdaNm) const;
  float maxValue() const;  // over 360..830 nm
};

// Coefficients for a linear sRGB reflectance in [0,1]^3 (clamped into it).
SigmoidPolynomial rgbToSigmoid(const Vec3& rgb);

// An unbounded RGB as scale * shape(lambda): scale = 2 max(rgb) (0 for black; negative and NaN
// components count as 0), shape = rgbToSigmoid(rgb / scale).
struct RgbUnbounded {
  SigmoidPolynomial shape;
  float scale = 0;
  float operator()(float lambdaNm) const { return scale * shape(lambdaNm); }
};
RgbUnbounded rgbToUnbounded(const Vec3& rgb);

// The three uses of an RGB triple (as in pbrt-v4):
//  - reflectance: clamped to [0,1], its spectrum stays in [0,1];
//  - unbounded (scattering coefficients, IOR-like data): scale = 2 max(rgb), shape of rgb/scale;
//  - illuminant: unbounded shape times the D65 spectrum, normalised so that rgb (1,1,1) has
//    luminance Y = 1 and develops to linear sRGB (1,1,1) (color/spectral_to_rgb.h convention).
Spectrum rgbReflectanceSpectrum(const Vec3& rgb, const Wavelengths& lambda);
Spectrum rgbUnboundedSpectrum(const Vec3& rgb, const Wavelengths& lambda);
Spectrum rgbIlluminantSpectrum(const Vec3& rgb, const Wavelengths& lambda);
// The same spectra of colours fitted beforehand (rgbToSigmoid, rgbToUnbounded), bit for bit:
// for a colour upsampled at many wavelength groups, fitted once.
Spectrum reflectanceSpectrum(const SigmoidPolynomial& shape, const Wavelengths& lambda);
Spectrum unboundedSpectrum(const RgbUnbounded& fitted, const Wavelengths& lambda);
Spectrum illuminantSpectrum(const RgbUnbounded& fitted, const Wavelengths& lambda);
float rgbReflectanceAt(const Vec3& rgb, float lambdaNm);
float rgbUnboundedAt(const Vec3& rgb, float lambdaNm);
float rgbIlluminantAt(const Vec3& rgb, float lambdaNm);

// Installs this upsampling as the language's (lang/rgb_upsampling.h: the builtins
// reflectance_spectrum, unbounded_spectrum, illuminant_spectrum). Also done by a static
// initialiser wherever this file is linked; programs call it to be explicit.
void installRgbUpsampling();

// D65 normalised so that its luminance Y is 1 under the radiance convention above.
float d65Normalised(float lambdaNm);

// Planck's law for a blackbody at `kelvin`, normalised to 1 at its peak wavelength.
float blackbodyNormalised(float lambdaNm, float kelvin);

}  // namespace tex::render
