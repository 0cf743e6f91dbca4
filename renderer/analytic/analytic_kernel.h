// The analytic kernel: a light-transport-free kernel for the stream runtime. Sample index i
// lands at the sampler's film position for i and records the known image's value there. In
// spectral mode it records a D65-shaped spectrum scaled by the value at a hero wavelength
// group (dimension 2), which develops to grey (v, v, v) up to spectral noise.
#pragma once
#include <cstdint>

#include "renderer/analytic/analytic_images.h"
#include "renderer/film/sample_record.h"
#include "renderer/sampling/sampler.h"
#include "runtime/stream.h"

namespace tex {

struct AnalyticKernel {
  sampling::Sampler sampler;
  AnalyticImage image = AnalyticImage::Gaussian;
  ValueKind valueKind = ValueKind::Scalar;
  int wavelengthCount = 4;  // spectral mode only

  SampleRecord record(uint64_t index) const;
  void operator()(uint64_t index, runtime::Emitter<SampleRecord>& out) const { out.emit(record(index)); }
};

}  // namespace tex
