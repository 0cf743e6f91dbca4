// The glossy model's kernel in the projected-disk ("direction cosine") plane
// (docs/glossy-model.md): k(q) = (1 - |q|^2)_+^(n/2) of the tangential momentum mismatch q,
// normalised over the plane to the density p(q) = (n + 2) / (2 pi) k(q). At normal incidence on
// a mirror this is cos^n of the angle to the mirror direction. Pure math in double precision
// (n = 4000 needs it: 1 - k ~ n q^2 / 2 with q ~ 0.02).
#pragma once

namespace tex::render::glossy {

// Planar density p(q) for |q|^2 = q2 (support: the unit disk). Integrates to 1 over the plane.
double kernelDensity(double exponent, double q2);

// Radius of a kernel sample from a uniform number u in [0,1): the radial CDF is
// 1 - (1 - r^2)^(n/2 + 1), inverted in closed form (expm1/log for large n).
double sampleKernelRadius(double exponent, double u);

// Share of the kernel, centred at distance `centreDistance` from the origin, that lies inside
// the disk of radius `diskRadius` (1D Gauss-Legendre quadrature over the radial CDF).
double kernelMassInDisk(double exponent, double centreDistance, double diskRadius);

// 32-point Gauss-Legendre quadrature of f over [0, 1].
template <class F>
double integrate01(F f);

// Nodes (positive half on [-1, 1]) and weights of the 32-point Gauss-Legendre rule.
extern const double kGaussNodes[16];
extern const double kGaussWeights[16];

template <class F>
double integrate01(F f) {
  double sum = 0.0;
  for (int i = 0; i < 16; ++i) sum += 0.5 * kGaussWeights[i] * (f(0.5 * (1.0 - kGaussNodes[i])) + f(0.5 * (1.0 + kGaussNodes[i])));
  return sum;
}

}  // namespace tex::render::glossy
