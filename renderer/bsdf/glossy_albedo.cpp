// The glossy reflection lobe's directional albedo by quadrature, and the table behind the
// energy-compensation lobe (docs/glossy-model.md, "Energy compensation").
#include "renderer/bsdf/glossy_albedo.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "renderer/bsdf/glossy_kernel.h"

namespace tex::render::glossy {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// The kernel's radial survival (1 - r^2)^(n/2 + 1): its mass beyond radius r.
double survivalAt(double n, double r) { return r >= 1.0 ? 0.0 : std::exp((0.5 * n + 1.0) * std::log1p(-r * r)); }

// Gauss-Legendre over [a, b] with t = (1 - cos(pi s)) / 2: nodes cluster at both ends, which
// tames the square-root behaviour where a circle first touches the rim.
template <class F>
double integrateClustered(F f, double a, double b) {
  if (!(b > a)) return 0.0;
  return integrate01([&](double s) {
    const double t = 0.5 * (1.0 - std::cos(kPiD * s));
    return (b - a) * 0.5 * kPiD * std::sin(kPiD * s) * f(a + (b - a) * t);
  });
}

}  // namespace

double reflectionAlbedoQuadrature(double n, double c) {
  if (!(n >= 0.0) || !std::isfinite(n) || !(c >= 0.0) || c > 1.0) return 0.0;
  const double d = std::sqrt(std::max(0.0, (1.0 - c) * (1.0 + c)));  // |wo_t| = kernel centre
  const double mo = kernelMassInDisk(n, d, 1.0);
  if (!(mo > 0.0)) return 0.0;
  // Beyond rEff the kernel's survival is < 1e-17: if every point within rEff of the centre has
  // its own kernel inside the disk too, M = 1 on both sides and the albedo is 1.
  const double rEff = sampleKernelRadius(n, 1e-17);
  if (d + 2.0 * rEff <= 1.0) return 1.0;
  // Integrand over the ring of radius r around the centre (angle phi from the outward
  // direction): (1/pi) int [|x| < 1] / max(mo, M(|x|)) dphi. M decreases with |x|, so the max
  // is mo where |x| >= d, i.e. cos(phi) >= -r / (2 d): that part is analytic.
  auto ring = [&](double r) -> double {
    double phi0 = 0.0;  // inside the unit disk for phi >= phi0
    if (d * r > 0.0) {
      const double cosLimit = (1.0 - d * d - r * r) / (2.0 * d * r);
      if (cosLimit <= -1.0) return 0.0;
      phi0 = cosLimit >= 1.0 ? 0.0 : std::acos(cosLimit);
    } else if (r >= 1.0) {
      return 0.0;
    }
    const double phiK = (d > 0.0 && r < 2.0 * d) ? std::acos(-r / (2.0 * d)) : kPiD;
    const double phiS = std::max(phi0, phiK);
    double sum = std::max(0.0, phiK - phi0) / mo;
    if (phiS < kPiD)
      sum += (kPiD - phiS) * integrate01([&](double t) {
               const double phi = phiS + (kPiD - phiS) * t;
               const double x2 = d * d + r * r + 2.0 * d * r * std::cos(phi);
               return 1.0 / std::max(mo, kernelMassInDisk(n, std::sqrt(std::max(0.0, x2)), 1.0));
             });
    return sum / kPiD;
  };
  // Outer integral over the kernel's own measure (survival u in [0, 1]), split at the radii
  // where the ring's integrand has kinks: r = 1 - d (touches the rim), r = 2 d (all |x| >= d).
  std::array<double, 4> radii = {0.0, 1.0 - d, 2.0 * d, 1.0};
  std::sort(radii.begin(), radii.end());
  double total = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double uHi = survivalAt(n, std::clamp(radii[k], 0.0, 1.0));
    const double uLo = survivalAt(n, std::clamp(radii[k + 1], 0.0, 1.0));
    total += integrateClustered([&](double u) { return ring(u > 0.0 ? sampleKernelRadius(n, u) : 1.0); }, uLo, uHi);
  }
  return std::min(total, 1.0);
}

namespace {

struct TableCoordinates {
  int i, j;
  double ts, tc;
};
// Cell and weights of (n, cos); false beyond the table (n > 2^kTableSMax - 1).
bool locate(double n, double c, TableCoordinates& out) {
  if (!(n >= 0.0)) return false;
  const double s = std::log2(1.0 + n);
  if (!(s <= kTableSMax)) return false;
  const double fs = s / kTableSMax * (kTableSNodes - 1);
  out.i = std::min(int(fs), kTableSNodes - 2);
  out.ts = fs - out.i;
  const double fc = std::clamp(c, 0.0, 1.0) * (kTableCosNodes - 1);
  out.j = std::min(int(fc), kTableCosNodes - 2);
  out.tc = fc - out.j;
  return true;
}

// 2 int_0^1 E_i(mu) mu dmu of node row i's piecewise-linear interpolant, exactly.
struct RowAverages {
  std::array<double, kTableSNodes> avg{};
  RowAverages() {
    const double h = 1.0 / (kTableCosNodes - 1);
    for (int i = 0; i < kTableSNodes; ++i) {
      double sum = 0.0;
      for (int j = 0; j + 1 < kTableCosNodes; ++j) {
        const double a = j * h, b = a + h;
        sum += h * (kAlbedoTable[i][j] * (2 * a + b) + kAlbedoTable[i][j + 1] * (a + 2 * b)) / 6.0;
      }
      avg[i] = 2.0 * sum;
    }
  }
};

}  // namespace

double tabulatedAlbedo(double n, double c) {
  TableCoordinates t;
  if (!locate(n, c, t)) return 1.0;
  auto row = [&](int i) { return (1.0 - t.tc) * kAlbedoTable[i][t.j] + t.tc * kAlbedoTable[i][t.j + 1]; };
  return (1.0 - t.ts) * row(t.i) + t.ts * row(t.i + 1);
}

double tabulatedAverageAlbedo(double n) {
  static const RowAverages rows;
  TableCoordinates t;
  if (!locate(n, 0.0, t)) return 1.0;
  return (1.0 - t.ts) * rows.avg[t.i] + t.ts * rows.avg[t.i + 1];
}

double compensationValue(double n, double cosO, double cosI) {
  const double eo = tabulatedAlbedo(n, cosO), ei = tabulatedAlbedo(n, cosI);
  if (!(eo < 1.0) || !(ei < 1.0)) return 0.0;
  const double avg = tabulatedAverageAlbedo(n);
  if (!(avg < 1.0)) return 0.0;
  return (1.0 - eo) * (1.0 - ei) / (kPiD * (1.0 - avg));
}

}  // namespace tex::render::glossy
