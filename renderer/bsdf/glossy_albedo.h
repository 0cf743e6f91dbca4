// Directional albedo E(n, cos theta_o) of the glossy reflection lobe p(q) / max(M(wo), M(wi))
// (docs/glossy-model.md) by deterministic quadrature, and its table for the reciprocal
// energy-compensation lobe (Kulla & Conty 2017): f_ms = (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg)).
#pragma once

namespace tex::render::glossy {

// Unit-weight albedo of the (uncompensated) glossy reflection lobe at cos(theta_o) in [0, 1].
// Nested Gauss-Legendre quadrature split at the lobe's kinks (the rim contact radius and the
// circle |x| = |wo_t| where the max switches sides); ~1e-6 accurate; a few ms per call.
double reflectionAlbedoQuadrature(double exponent, double cosThetaO);

// The table grid: s = log2(1 + n) in [0, kTableSMax] with kTableSNodes nodes, cos theta in
// [0, 1] with kTableCosNodes nodes. Values are E raised by kTableMargin (an upper bound on the
// bilinear interpolation error, measured by the generator) and clamped to 1, so that the
// interpolant is >= the true E: the compensated albedo E + (1 - E_table) is then <= 1.
inline constexpr int kTableSNodes = 81;
inline constexpr double kTableSMax = 20.0;
inline constexpr int kTableCosNodes = 129;
extern const double kTableMargin;
extern const float kAlbedoTable[kTableSNodes][kTableCosNodes];

// Bilinear table lookup of E (>= the true E; 1 for n beyond the table: no compensation).
double tabulatedAlbedo(double exponent, double cosTheta);
// 2 int_0^1 E_table(n, mu) mu dmu, exact for the interpolant (so the compensation lobe's
// albedo is exactly 1 - E_table(n, mu_o)).
double tabulatedAverageAlbedo(double exponent);

// The compensation lobe f_ms for cosines of wo and wi (same hemisphere; symmetric).
double compensationValue(double exponent, double cosO, double cosI);

}  // namespace tex::render::glossy
