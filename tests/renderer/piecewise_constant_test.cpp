// PiecewiseConstant1D (renderer/lights/piecewise_constant.h): its guided search must pick the
// cell a plain binary search over the whole CDF picks, with the same pmf and residual, bit for
// bit, on awkward weights (zeros, a spike, one cell) and at the guide's own boundaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/lights/piecewise_constant.h"
#include "renderer/sampling/pcg.h"

namespace tex::render {
namespace {

// The distribution's definition (pbrt-v4 A.4.2) written plainly: the first cell whose upper
// CDF bound exceeds u * total, never a zero-weight cell.
PiecewiseConstant1D::Sample reference(const std::vector<float>& weightsIn, float u) {
  std::vector<float> w = weightsIn;
  std::vector<double> cdf(w.size() + 1, 0.0);
  for (size_t i = 0; i < w.size(); ++i) {
    if (!(w[i] > 0.0f) || !std::isfinite(w[i])) w[i] = 0.0f;
    cdf[i + 1] = cdf[i] + double(w[i]);
  }
  const double total = cdf.back();
  const double target = double(u) * total;
  const int n = int(w.size());
  int i = int(std::upper_bound(cdf.begin() + 1, cdf.end(), target) - (cdf.begin() + 1));
  i = std::min(i, n - 1);
  while (i > 0 && w[size_t(i)] == 0.0f) --i;
  while (i < n - 1 && w[size_t(i)] == 0.0f) ++i;
  PiecewiseConstant1D::Sample s;
  s.index = i;
  s.pmf = total > 0 ? float(w[size_t(i)] / total) : 0.0f;
  const double wi = double(w[size_t(i)]);
  s.residual = float(std::clamp(wi > 0 ? (target - cdf[size_t(i)]) / wi : 0.0, 0.0, double(0x1.fffffep-1f)));
  return s;
}

std::vector<std::vector<float>> awkwardWeights() {
  std::vector<std::vector<float>> all;
  sampling::Pcg32 rng(17, 2);
  for (int n : {1, 2, 3, 5, 8, 37, 256, 1000}) {
    std::vector<float> w(static_cast<size_t>(n));
    for (float& x : w) x = rng.nextFloat() < 0.3f ? 0.0f : rng.nextFloat() * 10.0f;  // many zeros
    w[size_t(n) - 1] = std::max(w[size_t(n) - 1], 0.5f);
    all.push_back(w);
    std::vector<float> spike(size_t(n), 1e-6f);  // one cell holds nearly everything
    spike[size_t(n) / 2] = 1e6f;
    all.push_back(spike);
    std::vector<float> last(size_t(n), 0.0f);  // everything in the last cell
    last.back() = 3.0f;
    all.push_back(last);
    std::vector<float> broken(size_t(n), 1.0f);  // negative and non-finite weights count as 0
    if (n > 1) broken[0] = -1.0f;
    if (n > 2) broken[1] = std::nanf("");
    if (n > 3) broken[2] = INFINITY;
    all.push_back(broken);
  }
  return all;
}

TEST(PiecewiseConstant, GuidedSearchPicksTheWholeSearchsCellBitForBit) {
  sampling::Pcg32 rng(5, 9);
  int checked = 0;
  for (const std::vector<float>& w : awkwardWeights()) {
    const PiecewiseConstant1D d(w);
    ASSERT_GT(d.total(), 0.0);
    std::vector<float> us = {0.0f, 0x1.fffffep-1f, 0.5f};
    for (int i = 0; i < 2000; ++i) us.push_back(rng.nextFloat());
    // Around every fraction k / m a guide of m entries could use, the float on each side.
    for (int m : {1, 2, 3, 4, 10, 64, 250, 251}) {
      for (int k = 0; k <= m; ++k) {
        const float f = float(double(k) / double(m));
        for (float u : {std::nextafter(f, 0.0f), f, std::nextafter(f, 1.0f)})
          if (u >= 0.0f && u < 1.0f) us.push_back(u);
      }
    }
    for (float u : us) {
      const PiecewiseConstant1D::Sample got = d.sample(u), want = reference(w, u);
      ASSERT_EQ(got.index, want.index) << "n " << w.size() << " u " << u;
      ASSERT_EQ(got.pmf, want.pmf);
      ASSERT_EQ(got.residual, want.residual);
      ASSERT_GT(d.weight(got.index), 0.0f);
      ++checked;
    }
  }
  EXPECT_GT(checked, 60000);
}

}  // namespace
}  // namespace tex::render
