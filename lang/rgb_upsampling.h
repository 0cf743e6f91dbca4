// RGB to spectrum for the language's `reflectance_spectrum`, `unbounded_spectrum` and
// `illuminant_spectrum` builtins. The fitted Jakob & Hanika table belongs to the renderer
// (renderer/spectra/rgb_spectrum.h), which installs itself here; the interpreter and compiled
// code (through tex_rt_rgb_spectrum) both call the installed function, so they agree.
#pragma once
#include <cstdint>

namespace tex::lang {

enum class RgbUse : int32_t { Reflectance = 0, Unbounded = 1, Illuminant = 2 };

// Writes `count` values of the spectrum of `rgb` (linear sRGB) at lambdaNm[0..count).
using RgbToSpectrumFn = void (*)(RgbUse use, const float rgb[3], const float* lambdaNm, int count, float* out);

void setRgbToSpectrum(RgbToSpectrumFn fn);
// Calls the installed function; without one (a program that links no renderer) every value
// is NaN, so a missing upsampler cannot pass for a spectrum.
void rgbToSpectrum(RgbUse use, const float rgb[3], const float* lambdaNm, int count, float* out);

}  // namespace tex::lang
