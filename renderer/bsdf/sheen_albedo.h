// The "Charlie" sheen of Estevez & Kulla 2017 ("Production Friendly Microfacet Sheen BRDF", as
// glTF's KHR_materials_sheen uses it): its distribution, its fitted Lambda, the BRDF with unit
// colour, its directional albedo E(alpha, cos theta_o) by quadrature, and the table of E that
// the sheen lobes look up (renderer/bsdf/sheen_lobe.h).
//
// The fitted Lambda makes E exceed 1 in places: for alpha <= ~0.05 from cos theta ~ 0.05 down,
// and for every alpha within cos theta ~ 1e-5 of grazing (E(alpha = 1, 1e-6) ~ 1.5; measured by
// tests/renderer/sheen_test.cpp). The lobe therefore divides by max(1, E(wo), E(wi)) (symmetric:
// still reciprocal; albedo <= 1; unchanged wherever both E <= 1).
#pragma once

#include "renderer/core/geometry.h"

namespace tex::render::sheen {

// Roughness alpha (the paper's r: D ~ sin(theta_h)^(1/alpha)) is clamped to [kMinRoughness, 1];
// NaN is kMinRoughness.
inline constexpr double kMinRoughness = 0.01;
double clampRoughness(double alpha);

// D(theta_h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi); int D cos(theta_h) dw = 1.
double charlieD(double alpha, double cosThetaH);
// The paper's fitted Lambda (five parameters interpolated in (1 - alpha)^2), for |cos theta|.
double charlieLambda(double alpha, double cosTheta);
// D G2 / (4 |cos o| |cos i|) with G2 = 1 / (1 + Lambda(wo) + Lambda(wi)), unit colour, no
// normalisation; 0 unless wo and wi are in the same hemisphere (two-sided, like Lambertian).
double charlieValue(double alpha, const Vec3& wo, const Vec3& wi);

// E(alpha, mu) = int charlieValue |cos theta_i| dw_i, composite Gauss-Legendre (~1e-6
// accurate); tens of microseconds per call: for tests and the table generator only.
double albedoQuadrature(double alpha, double cosThetaO);

// The table grid: x = log(alpha / kMinRoughness) / log(1 / kMinRoughness) and
// y = log(mu / kTableMinCos) / log(1 / kTableMinCos), uniform in [0, 1]; mu below kTableMinCos
// reads the first column (the renderer's directions are degenerate there anyway). Node values
// are E raised by the largest bilinear-interpolation shortfall of their neighbouring cells
// (measured by the generator, times a safety factor), so the interpolant is >= the true E.
inline constexpr int kTableAlphaNodes = 48;
inline constexpr int kTableCosNodes = 96;
inline constexpr double kTableMinCos = 1e-6;
extern const float kAlbedoTable[kTableAlphaNodes][kTableCosNodes];

// Bilinear lookup of the table: >= E(alpha, mu) (may exceed 1, see above).
double tabulatedAlbedo(double alpha, double cosTheta);
// min(1, tabulatedAlbedo): the bound on the normalised sheen's albedo that the base under a
// sheen is scaled with (sheen_lobe.h).
double boundedAlbedo(double alpha, double cosTheta);
// 2 int_0^1 boundedAlbedo(alpha, mu) mu dmu, exact for the interpolant (piecewise analytic).
double boundedAverageAlbedo(double alpha);

}  // namespace tex::render::sheen
