// The coat of a layered BSDF (docs/layering.md): a dielectric interface (smooth or GGX) over
// base lobes. Private to renderer/bsdf/ (Bsdf::setCoat is the public entry point).
//  - Coat: the interface's reflection only, f_c (smooth: a Dirac mirror with F; rough: GGX).
//  - Base lobes flagged `underCoat` are scaled by
//      T(wo, wi) = (1 - F(cos_o)) (1 - F(cos_i)) / (1 - F_avg),
//    F_avg = 2 int_0^1 F(mu) mu dmu (the cosine-weighted external average). Since
//    1 - F_avg = eta^2 (1 - F_avg,internal), this is the classic smooth-coat-over-Lambertian
//    result with the 1/eta^2 of entering and the internal bounces of a white base summed
//    (Weidlich & Wilkie 2007; Mitsuba's smooth plastic): a white Lambertian under a smooth coat
//    has albedo exactly F(cos_o) + (1 - F(cos_o)) = 1. Directions are not refracted.
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"

namespace tex::render {

// 2 int_0^1 F(mu, eta) mu dmu for light arriving from outside (tabulated; eta in [1/4, 4]
// interpolated, outside computed directly).
float fresnelDielectricAverage(float eta);

bool coatIsSpecular(const Lobe& coat);
// The hero's Fresnel reflectance at wo (coat selection probability share).
float coatSelectionReflectance(const Lobe& coat, const Vec3& wo);
// Per-lane T(wo, wi) for Lambertian base lobes (1 where a lane's eta is invalid or 1).
Spectrum coatTransmittance(const Lobe& coat, const Vec3& wo, const Vec3& wi);
// Per-lane T for base lobes that scatter near the mirror direction (specular, conductor,
// glossy, sheen): 1 - max(F(cos_o), F(cos_i)). The Lambertian T's internal bounces average F
// over the hemisphere (F_avg), right for a base that spreads light everywhere; under a mirror
// the light bounces between coat and base at the same angle, and (1 - F)^2 / (1 - F_avg)
// exceeded 1 - F wherever F < F_avg: a coat over a mirror reflected 1.055 of the light. This
// T is 1 - F at the mirror direction (exact for a mirror: F + (1 - F) = 1), reciprocal, and
// never above 1 - F(cos_o), so a coated base of albedo <= 1 never gains energy.
Spectrum coatTransmittanceDirectional(const Lobe& coat, const Vec3& wo, const Vec3& wi);
// Whether a base lobe of this kind takes the Lambertian T (else the directional one).
inline bool spreadsOverTheHemisphere(LobeKind kind) {
  return kind == LobeKind::Lambertian || kind == LobeKind::LambertianUnderSheen;
}

Spectrum coatEval(const Lobe& coat, const Vec3& wo, const Vec3& wi);
float coatPdf(const Lobe& coat, const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> coatSample(const Lobe& coat, const Vec3& wo, Vec2 u2);

}  // namespace tex::render
