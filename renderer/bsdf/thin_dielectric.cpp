// Thin dielectric slab (a window pane): both interfaces with all internal bounces summed and
// no absorption. With R the single-interface Fresnel reflectance and T = 1 - R, the slab
// reflects R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) and transmits T' = 1 - R' straight
// through (wi = -wo: the two refractions cancel). Both events are Dirac (pbrt-v4 9.5.1,
// ThinDielectricBxDF). The directions do not depend on eta, so it is never dispersive: every
// lane carries its own R'_i (or T'_i) over the hero's event probability.
//
// A rough wall (GGX alpha > 0) is the model of thin-walled rough transmission used by the
// Enterprise PBR and OpenPBR specifications: a microfacet reflection whose Fresnel term is the
// slab's R'(wo.h), and a transmission that is the same lobe mirrored through the surface plane
// with 1 - R'(wo.h). Reflection and transmission together integrate to what the GGX reflection
// alone does (energy lost only to single-scattering masking), it is reciprocal (wo.h = wi.h and
// the mirror keeps both), and at alpha -> 0 it becomes the smooth slab. The wall's own
// roughness does not widen transmission twice (the two interfaces are one rough layer here).
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

namespace {

// wi mirrored onto wo's side of the surface when it lies on the other (the transmission that
// mirrors a reflection), with whether it was.
Vec3 reflectionSideOf(const Vec3& wo, const Vec3& wi, bool& transmitted) {
  transmitted = wo.z * wi.z < 0.0f;
  return transmitted ? Vec3(wi.x, wi.y, -wi.z) : wi;
}

// The hero's probability of the event (reflection or transmission) at the half vector h.
float heroEventProbability(const Lobe& lobe, float cosOh, bool transmitted) {
  const float heroEta = lobe.a.v[0];
  if (!(heroEta > 0.0f) || !std::isfinite(heroEta)) return 0.0f;
  const float r = thinDielectricReflectance(cosOh, heroEta);
  return transmitted ? 1.0f - r : r;
}

}  // namespace

Spectrum roughThinDielectricEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  bool transmitted = false;
  const Vec3 wiSide = reflectionSideOf(wo, wi, transmitted);
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, wiSide, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return Spectrum();
  const float kernel = ggxReflectionKernel(woUp, wiUp, h, clampGgxAlpha(lobe.roughness));
  const float cosOh = dot3(woUp, h);
  if (!std::isfinite(kernel) || !(cosOh > 0.0f)) return Spectrum();
  const float heroR = thinDielectricReflectance(cosOh, lobe.a.v[0]);
  Spectrum f;
  for (int i = 0; i < kLanes; ++i) {
    if (lobe.weight.v[i] == 0.0f) continue;
    const float r = lobe.etaVaries ? thinDielectricReflectance(cosOh, lobe.a.v[i]) : heroR;
    f.v[i] = lobe.weight.v[i] * (transmitted ? 1.0f - r : r) * kernel;
  }
  return f;
}

// The hero's density: the lanes' R' differ, the directions do not (not dispersive).
float roughThinDielectricPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  bool transmitted = false;
  const Vec3 wiSide = reflectionSideOf(wo, wi, transmitted);
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, wiSide, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return 0.0f;
  const float cosOh = dot3(woUp, h);
  return heroEventProbability(lobe, cosOh, transmitted) * ggxReflectionPairPdf(woUp, h, clampGgxAlpha(lobe.roughness));
}

std::optional<BsdfSample> roughThinDielectricSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2) {
  const std::optional<Vec3> reflected = ggxReflectionDirection(lobe, wo, u2);
  if (!reflected) return std::nullopt;
  Vec3 woUp, wiUp, h;
  if (!upperReflectionPair(wo, *reflected, woUp, wiUp) || !halfVector(woUp, wiUp, h)) return std::nullopt;
  const float heroR = heroEventProbability(lobe, dot3(woUp, h), false);
  BsdfSample s;
  s.transmission = !(uc < heroR);
  s.wi = s.transmission ? Vec3(reflected->x, reflected->y, -reflected->z) : *reflected;
  s.pdfW = roughThinDielectricPdf(lobe, wo, s.wi);  // the same expression pdf() evaluates
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  s.f = roughThinDielectricEval(lobe, wo, s.wi);
  return s;
}

}  // namespace tex::render
