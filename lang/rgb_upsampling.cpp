#include "lang/rgb_upsampling.h"

#include <atomic>
#include <cmath>

namespace tex::lang {

namespace {
std::atomic<RgbToSpectrumFn> installed{nullptr};
}

void setRgbToSpectrum(RgbToSpectrumFn fn) { installed.store(fn, std::memory_order_release); }

void rgbToSpectrum(RgbUse use, const float rgb[3], const float* lambdaNm, int count, float* out) {
  if (RgbToSpectrumFn fn = installed.load(std::memory_order_acquire)) {
    fn(use, rgb, lambdaNm, count, out);
    return;
  }
  for (int i = 0; i < count; ++i) out[i] = NAN;
}

}  // namespace tex::lang
