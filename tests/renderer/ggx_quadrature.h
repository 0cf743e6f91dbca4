// Midpoint quadrature in (cos theta, phi) over the upper hemisphere of GGX's projected normal
// distribution, int D(m) cos(theta_m) dm, and of the visible normals seen from wo,
// int D_wo(m) dm (Heitz 2014, eqs. 4 and 38): both are 1.
#pragma once
#include <cmath>

#include "renderer/bsdf/microfacet.h"

namespace tex::test {

using render::GgxAlpha;
using render::Vec3;

struct GgxIntegrals {
  double projected = 0, visible = 0;
};

inline GgxIntegrals ggxNormalisation(const GgxAlpha& alpha, const Vec3& wo, int nTheta, int nPhi) {
  GgxIntegrals sum;
  const double dOmega = (1.0 / nTheta) * (2 * M_PI / nPhi);
  for (int i = 0; i < nTheta; ++i)
    for (int j = 0; j < nPhi; ++j) {
      const double cosT = (i + 0.5) / nTheta, phi = (j + 0.5) * 2 * M_PI / nPhi;
      const double sinT = std::sqrt(1 - cosT * cosT);
      const Vec3 m(float(sinT * std::cos(phi)), float(sinT * std::sin(phi)), float(cosT));
      sum.projected += render::ggxD(m, alpha) * cosT * dOmega;
      if (render::dot3(wo, m) > 0) sum.visible += render::ggxVisibleD(wo, m, alpha) * dOmega;
    }
  return sum;
}

}  // namespace tex::test
