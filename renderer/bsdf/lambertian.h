// The Lambertian lobe in the local shading frame (z = normal): f = weight / pi on wo's side,
// cosine-weighted sampling. Inline (private to renderer/bsdf/): the lobe mixture calls these
// directly for the commonest lobe instead of going through lobeSample's dispatch and its large
// stack frame; lobes.cpp's dispatch uses the same functions, so the arithmetic is one copy.
#pragma once
#include <cmath>
#include <optional>

#include "renderer/bsdf/bsdf.h"
#include "renderer/core/warp.h"

namespace tex::render {

inline Spectrum lambertianEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  return sameHemisphere(wo, wi) ? lobe.weight * kInvPi : Spectrum();
}

inline float lambertianPdf(const Vec3& wo, const Vec3& wi) {
  return sameHemisphere(wo, wi) ? absCosTheta(wi) * kInvPi : 0.0f;
}

inline std::optional<BsdfSample> lambertianSample(const Lobe& lobe, const Vec3& wo, Vec2 u2) {
  if (!(std::fabs(wo.z) > 0.0f)) return std::nullopt;  // also rejects NaN
  Vec3 wi = sampleCosineHemisphere(u2);
  if (wo.z < 0.0f) wi.z = -wi.z;  // reflection stays on wo's side (two-sided diffuse)
  if (wi.z == 0.0f) return std::nullopt;  // the disk's rim: zero density
  BsdfSample s;
  s.wi = wi;
  s.f = lobe.weight * kInvPi;
  s.pdfW = absCosTheta(wi) * kInvPi;
  return s;
}

}  // namespace tex::render
