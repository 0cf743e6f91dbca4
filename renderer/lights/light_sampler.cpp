// LightSampler (light.h): lights chosen in proportion to power() by inverting the CDF.
#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/lights/light.h"

namespace tex::render {

LightSampler::LightSampler(std::span<const Light* const> lights) {
  pmf_.resize(lights.size(), 0.0f);
  double total = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    const float p = lights[i] ? lights[i]->power() : 0.0f;
    // Broken (NaN) or dark lights are never chosen. A power that overflowed (a sun over a scene
    // of huge bounds, pi R^2 E) still counts, as the largest float: any positive choice
    // probability is unbiased, and the light is no longer left out (a black image).
    pmf_[i] = std::isfinite(p) && p > 0.0f ? p : p == std::numeric_limits<float>::infinity() ? std::numeric_limits<float>::max() : 0.0f;
    total += pmf_[i];
  }
  cdf_.resize(lights.size(), 0.0f);
  double running = 0;
  for (size_t i = 0; i < pmf_.size(); ++i) {
    pmf_[i] = total > 0 ? float(pmf_[i] / total) : 0.0f;
    running += pmf_[i];
    cdf_[i] = float(running);
  }
}

float LightSampler::pmf(int lightIndex) const {
  return lightIndex >= 0 && lightIndex < size() ? pmf_[size_t(lightIndex)] : 0.0f;
}

}  // namespace tex::render
