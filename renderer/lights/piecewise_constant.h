// A discrete distribution proportional to non-negative weights, sampled by inverting its CDF
// (pbrt-v4, section A.4.2): the building block of the environment map's 2D distribution.
#pragma once
#include <cstddef>
#include <vector>

namespace tex::render {

class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  // Negative and non-finite weights count as 0.
  explicit PiecewiseConstant1D(const std::vector<float>& weights);

  int size() const { return int(weights_.size()); }
  double total() const { return total_; }
  float weight(int i) const { return weights_[size_t(i)]; }
  // Probability of cell i (0 when every weight is 0).
  float pmf(int i) const { return total_ > 0 ? float(weights_[size_t(i)] / total_) : 0.0f; }

  // The floats first: returned in registers, {pmf, residual} is one SSE register and index
  // another; in the order {index, pmf, residual} GCC assembled it on the stack and read it back
  // with a load spanning two narrower stores (a store-forwarding stall on every sample).
  struct Sample {
    float pmf = 0;
    float residual = 0;  // where u fell inside the cell, in [0,1): a fresh uniform number
    int index = 0;
  };
  // Never returns a zero-weight cell; requires total() > 0.
  Sample sample(float u) const;

 private:
  std::vector<float> weights_;
  std::vector<double> cdf_;  // size + 1 entries, cdf_[0] = 0 (double: large maps sum many pixels)
  double total_ = 0;
  // guide_[k]: the cell holding the fraction k / (guide size - 1) of the total, so that a
  // sample searches only the cells between two guide entries (a few, instead of a binary
  // search over the whole CDF) and finds the cell the whole search would.
  std::vector<int> guide_;
  int searchWhole(double target) const;
};

}  // namespace tex::render
