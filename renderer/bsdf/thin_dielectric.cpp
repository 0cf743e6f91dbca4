// Thin dielectric slab (a window pane): both interfaces with all internal bounces summed and
// no absorption. With R the single-interface Fresnel reflectance and T = 1 - R, the slab
// reflects R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) and transmits T' = 1 - R' straight
// through (wi = -wo: the two refractions cancel). Both events are Dirac (pbrt-v4 9.5.1,
// ThinDielectricBxDF). The directions do not depend on eta, so it is never dispersive: every
// lane carries its own R'_i (or T'_i) over the hero's event probability.
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/microfacet.h"

namespace tex::render {

float thinDielectricReflectance(float cosThetaO, float eta) {
  const float r = fresnelDielectric(std::fabs(cosThetaO), eta);
  return r < 1.0f ? 2.0f * r / (1.0f + r) : 1.0f;
}

std::optional<BsdfSample> thinDielectricSample(const Lobe& lobe, const Vec3& wo, float uc) {
  const float cosO = std::fabs(wo.z);
  if (!(cosO >= kMinCosTheta)) return std::nullopt;
  const float heroEta = lobe.a.v[0];
  if (!(heroEta > 0.0f) || !std::isfinite(heroEta)) return std::nullopt;
  const float heroR = thinDielectricReflectance(cosO, heroEta);
  const bool reflected = uc < heroR;
  BsdfSample s;
  s.specular = true;
  s.wi = reflected ? Vec3(-wo.x, -wo.y, wo.z) : -wo;
  s.transmission = !reflected;
  s.pdfW = reflected ? heroR : 1.0f - heroR;
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  const float invCos = 1.0f / cosO;
  for (int i = 0; i < kLanes; ++i) {
    if (lobe.weight.v[i] == 0.0f) continue;
    const float r = lobe.etaVaries ? thinDielectricReflectance(cosO, lobe.a.v[i]) : heroR;
    s.f.v[i] = lobe.weight.v[i] * (reflected ? r : 1.0f - r) * invCos;
  }
  return s;
}

}  // namespace tex::render
