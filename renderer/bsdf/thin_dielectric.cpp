// Thin dielectric slab (a window pane): both interfaces with all internal bounces summed and
// no absorption. With R the single-interface Fresnel reflectance and T = 1 - R, the slab
// reflects R' = R + T^2 R / (1 - R^2) = 2R / (1 + R) and transmits T' = 1 - R' straight
// through (wi = -wo: the two refractions cancel). Both events are Dirac (pbrt-v4 9.5.1,
// ThinDielectricBxDF). The directions do not depend on eta, so it is never dispersive: every
// lane carries its own R'_i (or T'_i) over the hero's event probability. The lobe's `b` tints
// the transmission only (glTF's thin-walled transmission: the base colour filters the light
// passing the wall, never its reflection); events are still chosen by R' and T', so a tint of 0
// in some lanes costs variance, never bias.
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

Spectrum thinDielectricStraightThrough(const Lobe& lobe, float cosTheta) {
  Spectrum t;
  const float cosO = std::fabs(cosTheta);
  if (!(cosO >= kMinCosTheta) || !(lobe.a.v[0] > 0.0f) || !std::isfinite(lobe.a.v[0])) return t;
  const float heroR = thinDielectricReflectance(cosO, lobe.a.v[0]);
  for (int i = 0; i < kLanes; ++i) {
    if (lobe.weight.v[i] == 0.0f) continue;
    const float r = lobe.etaVaries ? thinDielectricReflectance(cosO, lobe.a.v[i]) : heroR;
    t.v[i] = lobe.weight.v[i] * (1.0f - r) * lobe.b.v[i];
  }
  return t;
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
    s.f.v[i] = lobe.weight.v[i] * (reflected ? r : (1.0f - r) * lobe.b.v[i]) * invCos;
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

namespace {

// The reflection pair behind (wo, wi): wi mirrored onto wo's side when it is a transmission.
struct WallPair {
  bool transmitted = false;
  Vec3 woUp, wiUp, h;
  float cosOh = 0;
};

std::optional<WallPair> wallPair(const Vec3& wo, const Vec3& wi) {
  WallPair p;
  const Vec3 wiSide = reflectionSideOf(wo, wi, p.transmitted);
  if (!upperReflectionPair(wo, wiSide, p.woUp, p.wiUp) || !halfVector(p.woUp, p.wiUp, p.h)) return std::nullopt;
  p.cosOh = dot3(p.woUp, p.h);
  return p;
}

Spectrum wallEval(const Lobe& lobe, const WallPair& p) {
  const float kernel = ggxReflectionKernel(p.woUp, p.wiUp, p.h, clampGgxAlpha(lobe.roughness));
  if (!std::isfinite(kernel) || !(p.cosOh > 0.0f)) return Spectrum();
  const float heroR = thinDielectricReflectance(p.cosOh, lobe.a.v[0]);
  Spectrum f;
  for (int i = 0; i < kLanes; ++i) {
    if (lobe.weight.v[i] == 0.0f) continue;
    const float r = lobe.etaVaries ? thinDielectricReflectance(p.cosOh, lobe.a.v[i]) : heroR;
    f.v[i] = lobe.weight.v[i] * (p.transmitted ? (1.0f - r) * lobe.b.v[i] : r) * kernel;
  }
  return f;
}

// The hero's density: the lanes' R' differ, the directions do not (not dispersive).
float wallPdf(const Lobe& lobe, const WallPair& p) {
  return heroEventProbability(lobe, p.cosOh, p.transmitted) * ggxReflectionPairPdf(p.woUp, p.h, clampGgxAlpha(lobe.roughness));
}

}  // namespace

Spectrum roughThinDielectricEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  const std::optional<WallPair> p = wallPair(wo, wi);
  return p ? wallEval(lobe, *p) : Spectrum();
}

float roughThinDielectricPdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  const std::optional<WallPair> p = wallPair(wo, wi);
  return p ? wallPdf(lobe, *p) : 0.0f;
}

std::optional<BsdfSample> roughThinDielectricSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2) {
  const std::optional<Vec3> reflected = ggxReflectionDirection(lobe, wo, u2);
  if (!reflected) return std::nullopt;
  // One pair serves both events: a transmission mirrors the reflection back onto wo's side
  // exactly, so pdf() and eval() of the sampled direction give these same values.
  std::optional<WallPair> p = wallPair(wo, *reflected);
  if (!p) return std::nullopt;
  BsdfSample s;
  s.transmission = !(uc < heroEventProbability(lobe, p->cosOh, false));
  p->transmitted = s.transmission;
  s.wi = s.transmission ? Vec3(reflected->x, reflected->y, -reflected->z) : *reflected;
  s.pdfW = wallPdf(lobe, *p);
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  s.f = wallEval(lobe, *p);
  return s;
}

}  // namespace tex::render
