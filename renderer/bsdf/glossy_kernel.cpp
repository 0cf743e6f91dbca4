// The glossy kernel's density, radial sampling and its mass inside an offset disk (the
// normalisation M of docs/glossy-model.md).
#include "renderer/bsdf/glossy_kernel.h"

#include <algorithm>
#include <cmath>

namespace tex::render::glossy {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// 32-point Gauss-Legendre nodes and weights on [-1, 1] (positive half; symmetric).
}  // namespace

const double kGaussNodes[16] = {
    0.0483076656877383162, 0.1444719615827964934, 0.2392873622521370745, 0.3318686022821276498,
    0.4213512761306353454, 0.5068999089322293900, 0.5877157572407623290, 0.6630442669302152010,
    0.7321821187402896804, 0.7944837959679424070, 0.8493676137325699701, 0.8963211557660521240,
    0.9349060759377396892, 0.9647622555875064308, 0.9856115115452683354, 0.9972638618494815635};

const double kGaussWeights[16] = {
    0.0965400885147278006, 0.0956387200792748594, 0.0938443990808045654, 0.0911738786957638847,
    0.0876520930044038111, 0.0833119242269467552, 0.0781938957870703065, 0.0723457941088485062,
    0.0658222227763618468, 0.0586840934785355471, 0.0509980592623761762, 0.0428358980222266807,
    0.0342738629130214331, 0.0253920653092620595, 0.0162743947309056706, 0.0070186100094700966};

namespace {

// log of (1 - r^2)^(n/2 + 1): the radial survival function at r (log domain: it underflows).
double logSurvival(double exponent, double r) {
  if (r >= 1.0) return -INFINITY;
  return (0.5 * exponent + 1.0) * std::log1p(-r * r);
}

// Fraction of the circle of radius r around a centre at distance d inside the disk of radius R.
double arcFractionInside(double d, double r, double R) {
  if (d + r <= R) return 1.0;
  if (r >= d + R || r <= d - R) return 0.0;
  const double c = (d * d + r * r - R * R) / (2.0 * d * r);
  return std::acos(std::clamp(c, -1.0, 1.0)) / kPiD;
}

}  // namespace

double kernelDensity(double exponent, double q2) {
  if (!(q2 < 1.0)) return 0.0;
  return (exponent + 2.0) / (2.0 * kPiD) * std::exp(0.5 * exponent * std::log1p(-q2));
}

double sampleKernelRadius(double exponent, double u) {
  if (!(u > 0.0)) return 1.0;
  // 1 - r^2 = u^(2 / (n + 2))  =>  r^2 = -expm1(2 log(u) / (n + 2)), exact for tiny r^2.
  const double r2 = -std::expm1(2.0 * std::log(u) / (exponent + 2.0));
  return std::sqrt(std::clamp(r2, 0.0, 1.0));
}

double kernelMassInDisk(double exponent, double d, double R) {
  d = std::fabs(d);
  if (d + 1.0 <= R) return 1.0;  // the kernel's whole support is inside
  const double rLo = std::fabs(R - d), rHi = std::min(1.0, R + d);
  if (rLo >= 1.0) return d < R ? 1.0 : 0.0;
  // Radii below rLo are entirely inside (d < R) or entirely outside (d > R).
  const double logULo = logSurvival(exponent, rLo), logUHi = logSurvival(exponent, rHi);
  const double inner = d < R ? -std::expm1(logULo) : 0.0;
  const double uLo = std::exp(logULo), uHi = std::exp(logUHi);
  const double width = uLo - uHi;
  // The transition carries at most uLo of the mass: below 1e-16 it cannot change a double.
  if (!(width > 0.0) || uLo < 1e-16) return inner;
  // Transition radii: integrate the arc fraction over the survival u in [uHi, uLo]. The
  // substitution u = uHi + width (1 - cos(pi t)) / 2 removes the square-root behaviour of the
  // arc fraction at both ends (where the circle just touches the disk's rim).
  const double sum = integrate01([&](double t) {
    const double u = uHi + width * 0.5 * (1.0 - std::cos(kPiD * t));
    const double jacobian = width * 0.5 * kPiD * std::sin(kPiD * t);
    const double r = u > 0.0 ? sampleKernelRadius(exponent, u) : 1.0;
    return jacobian * arcFractionInside(d, r, R);
  });
  return std::clamp(inner + sum, 0.0, 1.0);
}

}  // namespace tex::render::glossy
