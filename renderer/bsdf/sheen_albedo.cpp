// The Charlie sheen's formulas, its albedo by quadrature, and the lookups of its albedo table
// (the table itself: sheen_albedo_table.cpp).
#include "renderer/bsdf/sheen_albedo.h"

#include <algorithm>
#include <cmath>

#include "renderer/bsdf/glossy_kernel.h"

namespace tex::render::sheen {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// The fit's parameters at alpha = 1 and at alpha = 0 (Estevez & Kulla 2017, table 1; the
// values glTF's KHR_materials_sheen lists), blended with t = (1 - alpha)^2.
constexpr double kFitAtOne[5] = {21.5473, 3.82987, 0.19823, -1.97760, -4.32054};
constexpr double kFitAtZero[5] = {25.3245, 3.32435, 0.16801, -1.27393, -4.85967};

// L(x) = a / (1 + b x^c) + d x + e.
double fitL(double alpha, double x) {
  const double t = (1.0 - alpha) * (1.0 - alpha);
  double p[5];
  for (int k = 0; k < 5; ++k) p[k] = kFitAtOne[k] + t * (kFitAtZero[k] - kFitAtOne[k]);
  return p[0] / (1.0 + p[1] * std::pow(x, p[2])) + p[3] * x + p[4];
}

// Composite 32-point Gauss-Legendre over [a, b] in `pieces` equal parts.
template <class F>
double integrate(F f, double a, double b, int pieces) {
  const double h = (b - a) / pieces;
  double sum = 0.0;
  for (int k = 0; k < pieces; ++k) sum += h * glossy::integrate01([&](double s) { return f(a + h * (k + s)); });
  return sum;
}

// Table coordinates in [0, 1] (header).
double gridX(double alpha) {
  return std::clamp(std::log(clampRoughness(alpha) / kMinRoughness) / std::log(1.0 / kMinRoughness), 0.0, 1.0);
}
double gridY(double mu) {
  const double m = std::clamp(std::isnan(mu) ? kTableMinCos : mu, kTableMinCos, 1.0);
  return std::clamp(std::log(m / kTableMinCos) / std::log(1.0 / kTableMinCos), 0.0, 1.0);
}

// Row i and weight tx of alpha's place in the table.
void alphaCell(double alpha, int& i, double& tx) {
  const double x = gridX(alpha) * (kTableAlphaNodes - 1);
  i = std::min(int(x), kTableAlphaNodes - 2);
  tx = x - i;
}

// The table row blended at alpha's place, at column j.
double rowValue(int i, double tx, int j) {
  return (1.0 - tx) * double(kAlbedoTable[i][j]) + tx * double(kAlbedoTable[i + 1][j]);
}

// 2 int g(v) mu dmu over v = ln(mu) in [v0, v1] for g linear in v (g0 at v0, g1 at v1):
// with d(mu^2) = 2 e^(2v) dv, an antiderivative of (p + q v) 2 e^(2v) is e^(2v) (p + q v - q / 2).
double cosineWeightedLinear(double v0, double v1, double g0, double g1) {
  if (!(v1 > v0)) return 0.0;
  const double q = (g1 - g0) / (v1 - v0), p = g0 - q * v0;
  auto antiderivative = [&](double v) { return std::exp(2.0 * v) * (p + q * v - 0.5 * q); };
  return antiderivative(v1) - antiderivative(v0);
}

// The same for min(1, g): split where g crosses 1.
double cosineWeightedBounded(double v0, double v1, double g0, double g1) {
  if (g0 <= 1.0 && g1 <= 1.0) return cosineWeightedLinear(v0, v1, g0, g1);
  if (g0 >= 1.0 && g1 >= 1.0) return std::exp(2.0 * v1) - std::exp(2.0 * v0);
  const double vc = v0 + (1.0 - g0) / (g1 - g0) * (v1 - v0);
  return g0 < 1.0 ? cosineWeightedLinear(v0, vc, g0, 1.0) + (std::exp(2.0 * v1) - std::exp(2.0 * vc))
                  : (std::exp(2.0 * vc) - std::exp(2.0 * v0)) + cosineWeightedLinear(vc, v1, 1.0, g1);
}

}  // namespace

double clampRoughness(double alpha) { return std::isnan(alpha) ? kMinRoughness : std::clamp(alpha, kMinRoughness, 1.0); }

double charlieD(double alpha, double cosThetaH) {
  const double invAlpha = 1.0 / clampRoughness(alpha);
  const double sin2 = std::max(0.0, 1.0 - cosThetaH * cosThetaH);
  return (2.0 + invAlpha) * std::pow(sin2, 0.5 * invAlpha) / (2.0 * kPiD);
}

double charlieLambda(double alpha, double cosTheta) {
  const double a = clampRoughness(alpha);
  const double c = std::min(std::fabs(cosTheta), 1.0);
  // The fit covers cos < 0.5; above it the paper mirrors it around 0.5 (smooth to first order).
  return c < 0.5 ? std::exp(fitL(a, c)) : std::exp(2.0 * fitL(a, 0.5) - fitL(a, 1.0 - c));
}

double charlieValue(double alpha, const Vec3& wo, const Vec3& wi) {
  const double cosO = std::fabs(double(wo.z)), cosI = std::fabs(double(wi.z));
  if (!(double(wo.z) * double(wi.z) > 0.0)) return 0.0;  // other side, grazing or NaN
  const double hx = double(wo.x) + wi.x, hy = double(wo.y) + wi.y, hz = cosO + cosI;
  const double length = std::sqrt(hx * hx + hy * hy + hz * hz);
  if (!(length > 0.0)) return 0.0;
  const double g2 = 1.0 / (1.0 + charlieLambda(alpha, cosO) + charlieLambda(alpha, cosI));
  return charlieD(alpha, hz / length) * g2 / (4.0 * cosO * cosI);
}

double albedoQuadrature(double alpha, double cosThetaO) {
  const double mu = std::clamp(cosThetaO, 0.0, 1.0);
  if (!(mu > 0.0)) return 0.0;
  const Vec3 wo(float(std::sqrt(std::max(0.0, 1.0 - mu * mu))), 0.0f, float(mu));
  // Over phi in [0, pi] (the lobe is symmetric about wo's plane), times 2.
  auto ring = [&](double muI) {
    const double sinI = std::sqrt(std::max(0.0, 1.0 - muI * muI));
    return 2.0 * integrate(
                     [&](double phi) {
                       const Vec3 wi(float(sinI * std::cos(phi)), float(sinI * std::sin(phi)), float(muI));
                       return charlieValue(alpha, wo, wi) * muI;
                     },
                     0.0, kPiD, 4);
  };
  // mu_i in [0, 0.5] as 0.5 s^3 (nodes crowd toward grazing, where small alphas peak), and
  // [0.5, 1] apart: Lambda's two branches meet at 0.5 with a kink in the second derivative.
  const double low = integrate([&](double s) { return 1.5 * s * s * ring(0.5 * s * s * s); }, 0.0, 1.0, 2);
  const double high = integrate(ring, 0.5, 1.0, 2);
  return low + high;
}

double tabulatedAlbedo(double alpha, double cosTheta) {
  int i;
  double tx;
  alphaCell(alpha, i, tx);
  const double y = gridY(cosTheta) * (kTableCosNodes - 1);
  const int j = std::min(int(y), kTableCosNodes - 2);
  const double ty = y - j;
  return (1.0 - ty) * rowValue(i, tx, j) + ty * rowValue(i, tx, j + 1);
}

double boundedAlbedo(double alpha, double cosTheta) { return std::min(1.0, tabulatedAlbedo(alpha, cosTheta)); }

double boundedAverageAlbedo(double alpha) {
  int i;
  double tx;
  alphaCell(alpha, i, tx);
  const double vMin = std::log(kTableMinCos);
  // Below the first column the lookup is constant: its share is kTableMinCos^2 times it.
  double sum = kTableMinCos * kTableMinCos * std::min(1.0, rowValue(i, tx, 0));
  for (int j = 0; j + 1 < kTableCosNodes; ++j) {
    const double v0 = vMin * (1.0 - double(j) / (kTableCosNodes - 1));
    const double v1 = vMin * (1.0 - double(j + 1) / (kTableCosNodes - 1));
    sum += cosineWeightedBounded(v0, v1, rowValue(i, tx, j), rowValue(i, tx, j + 1));
  }
  return sum;
}

}  // namespace tex::render::sheen
