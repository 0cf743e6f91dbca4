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
  if (weights_.empty()) return;
  const size_t intervals = (weights_.size() + 3) / 4;  // about four cells per guide entry
  guide_.resize(intervals + 1);
  for (size_t k = 0; k <= intervals; ++k) guide_[k] = searchWhole(double(k) / double(intervals) * total_);
}

// The number of upper CDF bounds at or below the target: the first cell whose upper bound
// exceeds it (zero-weight cells have an empty interval, so they are skipped).
int PiecewiseConstant1D::searchWhole(double target) const {
  return int(std::upper_bound(cdf_.begin() + 1, cdf_.end(), target) - (cdf_.begin() + 1));
}

PiecewiseConstant1D::Sample PiecewiseConstant1D::sample(float u) const {
  const double target = double(u) * total_;
  const int n = size();
  // The guide brackets the answer: searchWhole(target) lies in [lo, hi]. k = floor(u * intervals)
  // is exact in double, so k / intervals <= u < (k + 1) / intervals, and rounding is monotonic:
  // the guide's targets satisfy T_k <= target <= T_(k+1), hence cdf_[lo] <= target and, when
  // hi < n, target < cdf_[hi + 1] (PiecewiseConstant.GuidedSearchPicksTheWholeSearchsCellBitForBit
  // checks u on both sides of every guide boundary).
  const int intervals = int(guide_.size()) - 1;
  const int k = std::clamp(int(double(u) * double(intervals)), 0, intervals - 1);
  const int lo = guide_[size_t(k)], hi = guide_[size_t(k) + 1];
  int i = lo + int(std::upper_bound(cdf_.begin() + 1 + lo, cdf_.begin() + 1 + std::min(hi, n), target) -
                   (cdf_.begin() + 1 + lo));
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
