// LightSampler (light.h): lights chosen in proportion to power() by inverting the CDF.
#include <algorithm>
#include <cmath>

#include "renderer/lights/light.h"

namespace tex::render {

LightSampler::LightSampler(std::span<const Light* const> lights) {
  pmf_.resize(lights.size(), 0.0f);
  double total = 0;
  for (size_t i = 0; i < lights.size(); ++i) {
    const float p = lights[i] ? lights[i]->power() : 0.0f;
    pmf_[i] = std::isfinite(p) && p > 0.0f ? p : 0.0f;  // broken or dark lights are never chosen
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

std::optional<std::pair<int, float>> LightSampler::sample(float u) const {
  // The first light whose CDF exceeds u; a zero-pmf light has the same CDF as its predecessor,
  // so upper_bound never lands on it, except past the end from rounding (then take the last
  // light with power).
  int i;
  if (cdf_.size() <= kLinearSearchMax) {
    // upper_bound's index by counting (no branch to mispredict on a random u): the CDF is
    // sorted, so the entries not above u come first; !(u < c) also counts all for a NaN u.
    i = 0;
    for (const float c : cdf_) i += !(u < c);
  } else {
    i = int(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin());
  }
  i = std::min(i, size() - 1);
  while (i >= 0 && pmf_[size_t(i)] == 0.0f) --i;
  if (i < 0) return std::nullopt;
  return std::make_pair(i, pmf_[size_t(i)]);
}

float LightSampler::pmf(int lightIndex) const {
  return lightIndex >= 0 && lightIndex < size() ? pmf_[size_t(lightIndex)] : 0.0f;
}

}  // namespace tex::render
