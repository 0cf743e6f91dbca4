// Chi-square goodness-of-fit tests for sampling routines (header-only, for the renderer tests).
// Method as in Mitsuba's and pbrt's sampling tests: draw N independent samples, histogram them
// into cells, integrate the claimed density over each cell numerically for the expected counts,
// pool cells whose expected count is below 5 (so the chi-square approximation holds), and
// reject when the p-value is below the significance corrected for the number of tests in the
// suite (Sidak: 1 - (1 - alpha)^(1/testCount)).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "renderer/core/geometry.h"
#include "renderer/sampling/pcg.h"

namespace tex::test {

struct ChiSquareResult {
  double statistic = 0;
  int degreesOfFreedom = 0;
  double pValue = 1;
  bool passed = false;
  std::string detail;  // for the failure message
};

// Regularized upper incomplete gamma Q(a, x) (series for x < a + 1, continued fraction
// otherwise; Numerical Recipes, section 6.2).
inline double upperIncompleteGammaQ(double a, double x) {
  if (x <= 0) return 1.0;
  const double lnPrefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(lnPrefix));
  }
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1) < 1e-15) break;
  }
  return std::exp(lnPrefix) * h;
}

// observed[i] and expected[i] are counts per cell (expected may sum to less than the sample
// count when some samples legitimately fail; pass the failure cell explicitly then).
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed, const std::vector<double>& expected,
                                     double significance = 0.01, int testCount = 1) {
  ChiSquareResult r;
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  double pooledObserved = 0, pooledExpected = 0;
  int cells = 0;
  std::ostringstream detail;
  for (size_t k : order) {
    if (expected[k] == 0) {
      if (observed[k] > 0) {
        r.detail = "a sample fell into cell " + std::to_string(k) + " whose expected count is 0";
        r.passed = false;
        r.pValue = 0;
        return r;
      }
      continue;
    }
    if (expected[k] < 5 || (pooledExpected > 0 && pooledExpected < 5)) {
      pooledObserved += observed[k];
      pooledExpected += expected[k];
      if (pooledExpected >= 5) {
        r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
        ++cells;
        pooledObserved = pooledExpected = 0;
      }
      continue;
    }
    const double diff = observed[k] - expected[k];
    r.statistic += diff * diff / expected[k];
    ++cells;
  }
  if (pooledExpected > 0) {
    r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
    ++cells;
  }
  r.degreesOfFreedom = std::max(1, cells - 1);
  r.pValue = upperIncompleteGammaQ(r.degreesOfFreedom / 2.0, r.statistic / 2.0);
  const double alpha = 1.0 - std::pow(1.0 - significance, 1.0 / testCount);
  r.passed = r.pValue >= alpha;
  detail << "chi2 = " << r.statistic << ", dof = " << r.degreesOfFreedom << ", p = " << r.pValue
         << " (threshold " << alpha << ")";
  r.detail = detail.str();
  return r;
}

// A direction sampler under test: returns a unit direction, or nothing when the sample fails.
// Its random numbers are u (2D) and u3 (for lobe selection and the like).
using DirectionSampler = std::function<std::optional<render::Vec3>(render::Vec2 u, float u3)>;
using DirectionPdf = std::function<double(const render::Vec3& w)>;

struct DirectionTestOptions {
  int samples = 1000000;
  int cosThetaBins = 40;  // cells are equal in solid angle: uniform in cos(theta) and phi
  int phiBins = 80;
  int subdivisions = 6;   // quadrature points per cell side for the expected counts
  double significance = 0.01;
  int testCount = 1;
  uint64_t seed = 1;
  // cos(theta) values where the density may jump (e.g. where a lobe is cut off by a constant
  // z). Midpoint quadrature across a jump misplaces up to half a sub-cell of mass, and when the
  // jump lies along a constant z the errors of all cells on that ring add up instead of
  // cancelling; a cell containing a break is integrated on each side of it separately.
  std::vector<double> cosThetaBreaks;
  // When > 0, each cell's quadrature is refined by doubling the points per side, from
  // `subdivisions` up to maxSubdivisions, until a doubling moves the cell's expected count by at
  // most refineTolerance x its standard deviation sqrt(count): for lobes narrower than a
  // sub-cell, which a fixed grid misweighs. Whole-cell doubling rather than recursive splitting:
  // local 2 x 2 splits were seen to stop early on a narrow peak, when two coarse estimates of a
  // small piece agreed by chance.
  double refineTolerance = 0;
  int maxSubdivisions = 1536;
};

// Midpoint rule for the integral of pdfW over the (cos theta, phi) rectangle, n x n points.
inline double midpointDirectionIntegral(const DirectionPdf& pdfW, double z0, double z1, double phi0, double phi1,
                                        int n) {
  double sum = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double z = z0 + (a + 0.5) / n * (z1 - z0);
      const double phi = phi0 + (b + 0.5) / n * (phi1 - phi0);
      const double r = std::sqrt(std::max(0.0, 1 - z * z));
      sum += pdfW(render::Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
    }
  return sum / (double(n) * n) * (z1 - z0) * (phi1 - phi0);
}

// Expected share of one cell: cut at the breaks inside it, each piece by the midpoint rule,
// refined when o.refineTolerance > 0.
inline double integrateDirectionCell(const DirectionPdf& pdfW, double zLo, double zHi, double phiLo, double phiHi,
                                     const DirectionTestOptions& o) {
  std::vector<double> cuts = {zLo};
  for (double z : o.cosThetaBreaks)
    if (z > zLo && z < zHi) cuts.push_back(z);
  cuts.push_back(zHi);
  std::sort(cuts.begin(), cuts.end());
  double integral = 0;
  for (size_t piece = 0; piece + 1 < cuts.size(); ++piece) {
    const double z0 = cuts[piece], z1 = cuts[piece + 1];
    int n = o.subdivisions;
    double estimate = midpointDirectionIntegral(pdfW, z0, z1, phiLo, phiHi, n);
    while (o.refineTolerance > 0 && 2 * n <= o.maxSubdivisions) {
      n *= 2;
      const double finer = midpointDirectionIntegral(pdfW, z0, z1, phiLo, phiHi, n);
      const double toleranceMass = o.refineTolerance * std::sqrt(std::max(finer * o.samples, 1.0)) / o.samples;
      const bool converged = std::fabs(finer - estimate) <= toleranceMass;
      estimate = finer;
      if (converged) break;
    }
    integral += estimate;
  }
  return integral;
}

// Chi-square of a direction sampler against its density per solid angle over the whole sphere
// (z up). Samples that fail count in a "no sample" cell whose expected share is 1 - the
// density's integral, so a sampler that loses energy it claims is caught too.
inline ChiSquareResult chiSquareDirections(const DirectionSampler& sample, const DirectionPdf& pdfW,
                                           const DirectionTestOptions& o = {}) {
  using render::Vec2;
  using render::Vec3;
  const int cells = o.cosThetaBins * o.phiBins;
  std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, 0.0);
  sampling::Pcg32 rng(o.seed, 0x9e3779b97f4a7c15ull ^ o.seed);
  for (int i = 0; i < o.samples; ++i) {
    const Vec2 u(rng.nextFloat(), rng.nextFloat());
    const float u3 = rng.nextFloat();
    const std::optional<Vec3> w = sample(u, u3);
    if (!w) {
      observed[cells] += 1;
      continue;
    }
    const float z = std::clamp(w->z, -1.0f, 1.0f);
    int ct = int((z + 1.0f) * 0.5f * o.cosThetaBins);
    ct = std::clamp(ct, 0, o.cosThetaBins - 1);
    double phi = std::atan2(double(w->y), double(w->x));
    if (phi < 0) phi += 2 * M_PI;
    int pb = std::clamp(int(phi / (2 * M_PI) * o.phiBins), 0, o.phiBins - 1);
    observed[ct * o.phiBins + pb] += 1;
  }
  double total = 0;
  const double cellSolidAngle = (2.0 / o.cosThetaBins) * (2 * M_PI / o.phiBins);
  for (int ct = 0; ct < o.cosThetaBins; ++ct)
    for (int pb = 0; pb < o.phiBins; ++pb) {
      const double zLo = -1.0 + ct * 2.0 / o.cosThetaBins, zHi = -1.0 + (ct + 1) * 2.0 / o.cosThetaBins;
      if (o.refineTolerance > 0 || std::any_of(o.cosThetaBreaks.begin(), o.cosThetaBreaks.end(),
                                               [&](double z) { return z > zLo && z < zHi; })) {
        const double p = integrateDirectionCell(pdfW, zLo, zHi, pb * 2 * M_PI / o.phiBins,
                                                (pb + 1) * 2 * M_PI / o.phiBins, o);
        expected[ct * o.phiBins + pb] = p * o.samples;
        total += p;
        continue;
      }
      double sum = 0;
      for (int a = 0; a < o.subdivisions; ++a)
        for (int b = 0; b < o.subdivisions; ++b) {
          const double z = -1.0 + (ct + (a + 0.5) / o.subdivisions) * 2.0 / o.cosThetaBins;
          const double phi = (pb + (b + 0.5) / o.subdivisions) * 2 * M_PI / o.phiBins;
          const double r = std::sqrt(std::max(0.0, 1 - z * z));
          sum += pdfW(Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
        }
      const double p = sum / (o.subdivisions * o.subdivisions) * cellSolidAngle;
      expected[ct * o.phiBins + pb] = p * o.samples;
      total += p;
    }
  expected[cells] = std::max(0.0, 1.0 - total) * o.samples;
  if (expected[cells] < 1e-3 * o.samples && observed[cells] == 0) expected[cells] = 0;  // quadrature error
  ChiSquareResult r = chiSquareTest(observed, expected, o.significance, o.testCount);
  r.detail += ", density integral " + std::to_string(total);
  return r;
}

// Chi-square of a sampler of points in a 2D domain [0,1)^2 against a density over that domain
// (any 2D parametrisation: film positions, triangle barycentrics mapped to a square, ...).
using PointSampler = std::function<std::optional<render::Vec2>(render::Vec2 u, float u3)>;
using PointPdf = std::function<double(render::Vec2 p)>;

inline ChiSquareResult chiSquarePoints(const PointSampler& sample, const PointPdf& pdf, int bins = 64,
                                       int samples = 1000000, int subdivisions = 6, double significance = 0.01,
                                       int testCount = 1, uint64_t seed = 1) {
  using render::Vec2;
  const int cells = bins * bins;
  std::vector<double> observed(cells + 1, 0.0), expected(cells + 1, 0.0);
  sampling::Pcg32 rng(seed, 0x632be59bd9b4e019ull ^ seed);
  for (int i = 0; i < samples; ++i) {
    const Vec2 u(rng.nextFloat(), rng.nextFloat());
    const std::optional<Vec2> p = sample(u, rng.nextFloat());
    if (!p || !(p->x >= 0 && p->x < 1 && p->y >= 0 && p->y < 1)) {
      observed[cells] += 1;
      continue;
    }
    observed[std::min(bins - 1, int(p->y * bins)) * bins + std::min(bins - 1, int(p->x * bins))] += 1;
  }
  double total = 0;
  for (int y = 0; y < bins; ++y)
    for (int x = 0; x < bins; ++x) {
      double sum = 0;
      for (int a = 0; a < subdivisions; ++a)
        for (int b = 0; b < subdivisions; ++b)
          sum += pdf(Vec2(float((x + (a + 0.5) / subdivisions) / bins), float((y + (b + 0.5) / subdivisions) / bins)));
      const double p = sum / (subdivisions * subdivisions) / (double(bins) * bins);
      expected[y * bins + x] = p * samples;
      total += p;
    }
  expected[cells] = std::max(0.0, 1.0 - total) * samples;
  if (expected[cells] < 1e-3 * samples && observed[cells] == 0) expected[cells] = 0;
  ChiSquareResult r = chiSquareTest(observed, expected, significance, testCount);
  r.detail += ", density integral " + std::to_string(total);
  return r;
}

}  // namespace tex::test
