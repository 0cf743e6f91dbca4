// A sample record: what a kernel writes for the film, the sample file and the viewer. The
// image is a continuous function; a record is one point sample of it.
#pragma once
#include <array>
#include <cstdint>

#include "renderer/color/wavelengths.h"

namespace tex {

// What a record's values mean (fixed for a whole stream / sample file).
enum class ValueKind : uint8_t {
  // values[j] = spectral radiance at lambdaNm[j] divided by that wavelength's pdf (per nm), so
  // the colour estimate is (1/n) sum_j cmf(lambda_j) values[j] / integral(y-bar).
  SpectralRadianceOverPdf = 0,
  // values[0] is a scalar intensity (grey); wavelengths are unused. Analytic kernels use it.
  Scalar = 1,
};

// Technique tags (which estimator produced the record). Integrators add their own values.
enum TechniqueTag : uint16_t {
  kTechniqueCamera = 0,    // an ordinary camera-path sample
  kTechniqueAnalytic = 1,  // the analytic test kernel
  kTechniqueLightSplat = 2,
};

struct SampleRecord {
  float filmX = 0, filmY = 0;  // continuous film position in [0,1)^2, x right, y down
  float weight = 1;            // the sample's weight in the film's weighted average
  uint16_t technique = kTechniqueCamera;
  uint8_t wavelengthCount = 0;  // 1..kMaxWavelengths used entries of lambdaNm / values
  uint8_t reserved = 0;
  std::array<float, color::kMaxWavelengths> lambdaNm{};
  std::array<float, color::kMaxWavelengths> values{};
};

}  // namespace tex
