#include "renderer/analytic/analytic_kernel.h"

#include "renderer/color/color.h"
#include "renderer/color/spectral_to_rgb.h"

namespace tex {

namespace {
// Scale that makes the D65 spectrum have luminance Y = 1 under the radiance convention of
// spectral_to_rgb.h (so it develops to sRGB white).
double d65RadianceScale() {
  static const double scale = 1.0 / double(color::radianceSpectrumToXyz([](float l) { return color::d65RelativePower(l); }).y);
  return scale;
}
}  // namespace

SampleRecord AnalyticKernel::record(uint64_t index) const {
  SampleRecord r;
  const sampling::FilmPosition p = sampler.filmPosition(index);
  r.filmX = p.x;
  r.filmY = p.y;
  r.weight = 1.0f;
  r.technique = kTechniqueAnalytic;
  const float value = analyticValue(image, p.x, p.y);
  if (valueKind == ValueKind::Scalar) {
    r.wavelengthCount = 1;
    r.values[0] = value;
    return r;
  }
  const color::WavelengthGroup group =
      color::sampleWavelengthGroup(sampler.get(index, sampling::kWavelengthDimension), wavelengthCount);
  r.wavelengthCount = uint8_t(group.count);
  const double scale = d65RadianceScale();
  for (int j = 0; j < group.count; ++j) {
    r.lambdaNm[j] = group.lambdaNm[j];
    r.values[j] = float(value * scale * color::d65RelativePower(group.lambdaNm[j]) / group.pdfLambda[j]);
  }
  return r;
}

}  // namespace tex
