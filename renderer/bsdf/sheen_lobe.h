// The sheen lobes (renderer/bsdf/sheen_albedo.h for the model), conventions of bsdf.h (local
// frame, z up; two-sided like Lambertian: reflection on wo's side):
//  - Sheen: the Charlie sheen of colour `weight` and roughness alpha = `roughness`, divided by
//    max(1, E(wo), E(wi)) (E: its tabulated unit-colour albedo) so that its albedo is <= 1 where
//    the fitted shadowing lets E exceed 1; reciprocal.
//  - LambertianUnderSheen: a Lambertian base of albedo `weight` under a sheen of colour `a`
//    (per lane, in [0, 1]) and roughness `roughness`, scaled per lane by the reciprocal
//    albedo scaling (1 - a Eb(wo)) (1 - a Eb(wi)) / (1 - a Eb_avg), Eb = min(1, E) and Eb_avg its
//    cosine-weighted mean (Kulla & Conty 2017's form): its albedo is exactly
//    weight (1 - a Eb(wo)), so sheen + base <= 1 for a white base and any sheen colour <= 1.
// Both are sampled cosine-weighted (pdfW = |cos theta_i| / pi on wo's side).
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"

namespace tex::render {

Spectrum sheenLobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float sheenLobePdf(const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> sheenLobeSample(const Lobe& lobe, const Vec3& wo, Vec2 u2);

}  // namespace tex::render
