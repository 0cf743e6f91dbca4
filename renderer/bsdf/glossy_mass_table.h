// The glossy kernel's mass inside an offset disk, M(n, d, R) = kernelMassInDisk (glossy_kernel.h),
// from a table instead of a 32-point quadrature per call (docs/glossy-model.md, "Cost"). The
// lobes evaluate M several times per direction and per wavelength, which made the quadrature
// ~90% of a glossy dielectric's render time.
//
// Grid: s = log2(1 + n) (step 1/4), log2 R (step 1/16), and the centre distance d over the
// kernel's transition zone [R - w, R + w] (129 nodes), w = the radius beyond which the kernel's
// mass is < 1e-16 (so outside the zone M is exactly 1 or 0, as the quadrature returns).
// Interpolation: Catmull-Rom in all three axes. Rows (fixed n and R) are filled on first use
// (thread-safe), ~0.2 ms each: a material touches only the rows around its own n and IORs.
//
// The result bounds M from above: interpolant + massTableMargin(n), clamped to 1 (the margin is
// the measured worst interpolation error, tested at random points; `glossy_albedo masscheck`
// checks every cell). An upper bound keeps the lobes' albedo <= 1 exactly (the normalisation
// may only over-estimate the mass). Outside the domain (n < kMassTableMinExponent, R outside
// [kMassTableMinRadius, kMassTableMaxRadius], n beyond the grid) it is the quadrature itself.
#pragma once

namespace tex::render::glossy {

inline constexpr double kMassTableMinExponent = 7.0;  // s = 3
inline constexpr double kMassTableMaxExponent = 1048575.0;  // s = 20
inline constexpr double kMassTableMinRadius = 0.5;
inline constexpr double kMassTableMaxRadius = 3.0;

// >= kernelMassInDisk(n, d, R), by at most ~2 * massTableMargin(n); exactly 1 where the kernel
// is clear of the rim inside (d <= R - w), exactly 0 where it is clear outside (d >= R + w).
double tabulatedMassInDisk(double exponent, double centreDistance, double diskRadius);

// Whether (n, R) is inside the table's domain (else tabulatedMassInDisk is the quadrature).
bool massTableCovers(double exponent, double diskRadius);

// The margin added to the interpolant at exponent n (larger for n < 63).
double massTableMargin(double exponent);

// The raw interpolant (no margin, no clamp) inside the domain, for the check tool and tests.
double interpolatedMassInDisk(double exponent, double centreDistance, double diskRadius);

}  // namespace tex::render::glossy
