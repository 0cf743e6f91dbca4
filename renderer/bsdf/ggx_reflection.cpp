// GGX reflection lobes: the rough conductor (complex Fresnel per lane) and the reflection-only
// dielectric interface used as a layer's coat. Both are two-sided: wo below the surface is
// mirrored to the upper side with wi (z -> -z), like the Lambertian lobe.
// f = w F(wo.h) D(h) G(wo, wi) / (4 cos_o cos_i) with h the half vector (Walter et al. 2007,
// eq. 20; Smith height-correlated G, Heitz 2014 eq. 99); sampled by visible normals (Heitz
// 2018) with pdfW = D_wo(h) / (4 |wo.h|) (pbrt-v4 eq. 9.28).
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/microfacet.h"

namespace tex::render {

bool upperReflectionPair(const Vec3& wo, const Vec3& wi, Vec3& woUp, Vec3& wiUp) {
  if (!(std::fabs(wo.z) >= kMinCosTheta) || !(std::fabs(wi.z) >= kMinCosTheta) || !(wo.z * wi.z > 0.0f)) return false;
  const float s = wo.z > 0.0f ? 1.0f : -1.0f;
  woUp = Vec3(wo.x, wo.y, s * wo.z);
  wiUp = Vec3(wi.x, wi.y, s * wi.z);
  return true;
}

bool halfVector(const Vec3& woUp, const Vec3& wiUp, Vec3& h) {
  h = woUp + wiUp;
  const float len2 = lengthSquared(h);
  if (!(len2 > 1e-20f)) return false;
  h /= std::sqrt(len2);
  return true;
}

// D G / (4 cos_o cos_i): the Fresnel-free part of the BRDF.
float ggxReflectionKernel(const Vec3& woUp, const Vec3& wiUp, const Vec3& h, const GgxAlpha& alpha) {
  return ggxD(h, alpha) * ggxG(woUp, wiUp, alpha) / (4.0f * woUp.z * wiUp.z);
}

float ggxReflectionPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, wi, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return 0.0f;
  return ggxReflectionPairPdf(woUp, h, ggxAlphaOf(lobe));
}

float ggxReflectionPairPdf(const Vec3& woUp, const Vec3& h, const GgxAlpha& alpha) {
  const float cosOh = dot3(woUp, h);
  if (!(cosOh > 0.0f)) return 0.0f;
  const float pdfW = ggxVisibleD(woUp, h, alpha) / (4.0f * cosOh);
  return std::isfinite(pdfW) ? pdfW : 0.0f;
}

std::optional<Vec3> ggxReflectionDirection(const Lobe& lobe, const Vec3& wo, Vec2 u2) {
  if (!(std::fabs(wo.z) >= kMinCosTheta)) return std::nullopt;  // also NaN
  const float s = wo.z > 0.0f ? 1.0f : -1.0f;
  const Vec3 woUp(wo.x, wo.y, s * wo.z);
  const Vec3 m = ggxSampleVisibleNormal(woUp, ggxAlphaOf(lobe), u2);
  const Vec3 wiUp = reflect(woUp, m);
  if (!(wiUp.z >= kMinCosTheta)) return std::nullopt;
  return Vec3(wiUp.x, wiUp.y, s * wiUp.z);
}

Spectrum roughConductorEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, wi, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return Spectrum();
  const float kernel = ggxReflectionKernel(woUp, wiUp, h, ggxAlphaOf(lobe));
  if (!std::isfinite(kernel)) return Spectrum();
  return lobe.weight * fresnelConductor(dot3(woUp, h), lobe.a, lobe.b) * kernel;
}

float roughConductorPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) { return ggxReflectionPdf(lobe, wo, wi); }

std::optional<BsdfSample> roughConductorSample(const Lobe& lobe, const Vec3& wo, Vec2 u2) {
  const std::optional<Vec3> wi = ggxReflectionDirection(lobe, wo, u2);
  if (!wi) return std::nullopt;
  BsdfSample s;
  s.wi = *wi;
  s.pdfW = roughConductorPdf(lobe, wo, *wi);  // the same expression pdf() evaluates
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  s.f = roughConductorEval(lobe, wo, *wi);
  return s;
}

Spectrum ggxDielectricReflectionEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, wi, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return Spectrum();
  const float kernel = ggxReflectionKernel(woUp, wiUp, h, ggxAlphaOf(lobe));
  if (!std::isfinite(kernel)) return Spectrum();
  const float cosOh = dot3(woUp, h);
  Spectrum f;
  if (!lobe.etaVaries) {
    // One IOR for the whole group (a coat's always): one Fresnel term, not one per lane.
    const float fresnel = fresnelDielectric(cosOh, lobe.a.v[0]);
    for (int i = 0; i < kLanes; ++i)
      if (lobe.weight.v[i] != 0.0f) f.v[i] = lobe.weight.v[i] * fresnel * kernel;
    return f;
  }
  for (int i = 0; i < kLanes; ++i)
    if (lobe.weight.v[i] != 0.0f) f.v[i] = lobe.weight.v[i] * fresnelDielectric(cosOh, lobe.a.v[i]) * kernel;
  return f;
}

float ggxDielectricReflectionPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  return ggxReflectionPdf(lobe, wo, wi);
}

std::optional<BsdfSample> ggxDielectricReflectionSample(const Lobe& lobe, const Vec3& wo, Vec2 u2) {
  const std::optional<Vec3> wi = ggxReflectionDirection(lobe, wo, u2);
  if (!wi) return std::nullopt;
  BsdfSample s;
  s.wi = *wi;
  s.pdfW = ggxReflectionPdf(lobe, wo, *wi);
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  s.f = ggxDielectricReflectionEval(lobe, wo, *wi);
  return s;
}

}  // namespace tex::render
