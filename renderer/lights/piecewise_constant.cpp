#include "renderer/lights/piecewise_constant.h"

#include <algorithm>
#include <cmath>

namespace tex::render {

PiecewiseConstant1D::PiecewiseConstant1D(const std::vector<float>& weights) : weights_(weights) {
  cdf_.assign(weights_.size() + 1, 0.0);
  for (size_t i = 0; i < weights_.size(); ++i) {
    float& w = weights_[i];
    if (!(w > 0.0f) || !std::isfinite(w)) w = 0.0f;
    cdf_[i + 1] = cdf_[i] + double(w);
  }
  total_ = cdf_.back();
}

PiecewiseConstant1D::Sample PiecewiseConstant1D::sample(float u) const {
  const double target = double(u) * total_;
  // The first cell whose upper CDF bound exceeds the target; zero-weight cells have an
  // empty interval, so upper_bound skips them.
  const int n = size();
  int i = int(std::upper_bound(cdf_.begin() + 1, cdf_.end(), target) - (cdf_.begin() + 1));
  i = std::min(i, n - 1);
  while (i > 0 && weights_[size_t(i)] == 0.0f) --i;  // u rounded to the end of the range
  while (i < n - 1 && weights_[size_t(i)] == 0.0f) ++i;
  Sample s;
  s.index = i;
  s.pmf = pmf(i);
  const double w = double(weights_[size_t(i)]);
  const double r = w > 0 ? (target - cdf_[size_t(i)]) / w : 0.0;
  s.residual = float(std::clamp(r, 0.0, double(0x1.fffffep-1f)));
  return s;
}

}  // namespace tex::render
