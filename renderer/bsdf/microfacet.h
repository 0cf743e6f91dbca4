// GGX / Trowbridge-Reitz microfacet distribution (isotropic) and the lobes built on it:
// rough conductor, rough dielectric (Walter et al. 2007, "Microfacet Models for Refraction
// through Rough Surfaces"), plus the thin dielectric slab. Facts from pbrt-v4 section 9.6-9.7,
// Heitz 2014 ("Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs") and
// Heitz 2018 ("Sampling the GGX Distribution of Visible Normals"). Local frame, z = normal.
#pragma once
#include <optional>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/ggx_anisotropic.h"

namespace tex::render {

// Below this alpha the lobe is nearly a mirror but still has a (very peaked) density.
inline constexpr float kMinGgxAlpha = 1e-3f;
float clampGgxAlpha(float alpha);  // NaN / tiny -> kMinGgxAlpha
// The lobe's clamped alphas: isotropic (roughness) unless roughnessY is set and differs.
inline GgxAlpha ggxAlphaOf(const Lobe& lobe) {
  const float x = clampGgxAlpha(lobe.roughness);
  if (!(lobe.roughnessY > 0.0f)) return GgxAlpha(x);
  const float y = clampGgxAlpha(lobe.roughnessY);
  return x == y ? GgxAlpha(x) : GgxAlpha(x, y, lobe.anisotropyRotationRad);
}

// Normal distribution D(m) for a unit m (0 below the horizon).
float ggxD(const Vec3& m, float alpha);
// Smith's Lambda(w) for GGX; the height-correlated masking-shadowing G = 1/(1+L(wo)+L(wi)).
float ggxLambda(const Vec3& w, float alpha);
inline float ggxG1(const Vec3& w, float alpha) { return 1.0f / (1.0f + ggxLambda(w, alpha)); }
inline float ggxG(const Vec3& wo, const Vec3& wi, float alpha) {
  return 1.0f / (1.0f + ggxLambda(wo, alpha) + ggxLambda(wi, alpha));
}
// Density of visible normals seen from w (either side; m on the upper side):
// D_w(m) = G1(w) |w.m| D(m) / |cos w| (Heitz 2014, eq. 38).
float ggxVisibleD(const Vec3& w, const Vec3& m, float alpha);
// Samples m ~ D_w (m.z > 0; w below is treated as -w, so that w.m < 0 for it).
Vec3 ggxSampleVisibleNormal(const Vec3& w, float alpha, Vec2 u);
// Heitz 2018's core, shared by both samplers: a normal of the unit hemisphere distributed as
// its projected area seen from the (stretched, unit, upper) direction vh.
inline Vec3 visibleHemisphereNormal(const Vec3& vh, Vec2 u) {
  const float lenSq = vh.x * vh.x + vh.y * vh.y;
  const Vec3 t1 = lenSq > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lenSq) : Vec3(1.0f, 0.0f, 0.0f);
  const Vec3 t2 = glm::cross(vh, t1);
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  return p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
}

// The same with a lobe's alphas (ggx_anisotropic.h): equal alphas take the functions above.
inline float ggxD(const Vec3& m, const GgxAlpha& alpha) {
  return alpha.isotropic() ? ggxD(m, alpha.x) : ggxDAnisotropic(m, alpha);
}
inline float ggxLambda(const Vec3& w, const GgxAlpha& alpha) {
  return alpha.isotropic() ? ggxLambda(w, alpha.x) : ggxLambdaAnisotropic(w, alpha);
}
inline float ggxG1(const Vec3& w, const GgxAlpha& alpha) { return 1.0f / (1.0f + ggxLambda(w, alpha)); }
inline float ggxG(const Vec3& wo, const Vec3& wi, const GgxAlpha& alpha) {
  return 1.0f / (1.0f + ggxLambda(wo, alpha) + ggxLambda(wi, alpha));
}
inline float ggxVisibleD(const Vec3& w, const Vec3& m, const GgxAlpha& alpha) {
  return alpha.isotropic() ? ggxVisibleD(w, m, alpha.x) : ggxVisibleDAnisotropic(w, m, alpha);
}
inline Vec3 ggxSampleVisibleNormal(const Vec3& w, const GgxAlpha& alpha, Vec2 u) {
  return alpha.isotropic() ? ggxSampleVisibleNormal(w, alpha.x, u) : ggxSampleVisibleNormalAnisotropic(w, alpha, u);
}

// ---- GGX reflection geometry shared by the reflection lobes (ggx_reflection.cpp).
// The pair mirrored so that wo is on the upper side; false when not a usable reflection pair
// (either cosine below kMinCosTheta, or wo and wi on opposite sides).
bool upperReflectionPair(const Vec3& wo, const Vec3& wi, Vec3& woUp, Vec3& wiUp);
// The unit half vector of an upper pair; false when the two directions are opposite.
bool halfVector(const Vec3& woUp, const Vec3& wiUp, Vec3& h);
// D G / (4 cos_o cos_i): the Fresnel-free part of the reflection BRDF.
float ggxReflectionKernel(const Vec3& woUp, const Vec3& wiUp, const Vec3& h, const GgxAlpha& alpha);
// Visible-normal sampling's density of the reflected direction, D_wo(h) / (4 wo.h) (0 if not finite).
float ggxReflectionPairPdf(const Vec3& woUp, const Vec3& h, const GgxAlpha& alpha);
float ggxReflectionPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
// The reflection of wo about a visible normal drawn with u2, on wo's side (nothing when it
// points below the surface).
std::optional<Vec3> ggxReflectionDirection(const Lobe& lobe, const Vec3& wo, Vec2 u2);

// ---- Lobe entry points (dispatched from lobes.cpp).
Spectrum roughConductorEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float roughConductorPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> roughConductorSample(const Lobe& lobe, const Vec3& wo, Vec2 u2);

Spectrum roughDielectricEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode);
// The sampler's density if lane `lane`'s eta had chosen the direction (lane 0 = lobePdf).
float roughDielectricPdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, int lane);
std::optional<BsdfSample> roughDielectricSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode);

// Reflectance of a thin slab (both interfaces, internal bounces summed, no absorption):
// R' = R + T^2 R / (1 - R^2) with R the single-interface Fresnel reflectance (pbrt-v4 9.5.1).
float thinDielectricReflectance(float cosThetaO, float eta);
std::optional<BsdfSample> thinDielectricSample(const Lobe& lobe, const Vec3& wo, float uc);
// What a smooth thin wall passes straight through at |cos theta|: weight (1 - R') tint per lane
// (the weight of its Dirac transmission).
Spectrum thinDielectricStraightThrough(const Lobe& lobe, float cosTheta);
// A rough thin wall: GGX reflection with the slab's R'(wo.h), and transmission as that
// reflection mirrored through the surface plane with 1 - R' (thin_dielectric.cpp).
Spectrum roughThinDielectricEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float roughThinDielectricPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> roughThinDielectricSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2);

// GGX reflection of a dielectric interface only (the coat of a layer): f = w D G F / (4 cos cos),
// sampled by visible normals (density D_wo(m) / (4 |wo.m|)); two-sided (wo below is mirrored).
// Lane i's IOR is lobe.a.v[i] when lobe.etaVaries, else lobe.a.v[0] for every lane.
Spectrum ggxDielectricReflectionEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float ggxDielectricReflectionPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
std::optional<BsdfSample> ggxDielectricReflectionSample(const Lobe& lobe, const Vec3& wo, Vec2 u2);

}  // namespace tex::render
