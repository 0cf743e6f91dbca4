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
// Per-lane T(wo, wi) for base lobes (1 where a lane's eta is invalid or 1).
Spectrum coatTransmittance(const Lobe& coat, const Vec3& wo, const Vec3& wi);

Spectrum coatEval(const Lobe& coat, const Vec3& wo, const Vec3& wi);
float coatPdf(const Lobe& coat, const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> coatSample(const Lobe& coat, const Vec3& wo, Vec2 u2);

}  // namespace tex::render
