// The native BSDF lobes in the local shading frame (z = shading normal): Lambertian, smooth
// dielectric and smooth conductor here; GGX and thin-slab lobes in microfacet.h's files. Dispatch is a switch on the kind (no virtual calls); the
// specular lobes follow bsdf.h's Dirac convention (eval = pdf = 0, sample returns R / |cos|
// and the discrete probability of the chosen event).
#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/glossy_lobe.h"
#include "renderer/bsdf/lambertian.h"
#include "renderer/bsdf/microfacet.h"
#include "renderer/bsdf/sheen_lobe.h"
#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/core/warp.h"

namespace tex::render {
namespace {

// ---- Smooth dielectric: Fresnel-weighted choice between mirror reflection and refraction.

std::optional<BsdfSample> dielectricSample(const Lobe& lobe, const Vec3& wo, float uc, TransportMode mode) {
  const float cosO = std::fabs(wo.z);
  if (!(cosO >= kMinCosTheta)) return std::nullopt;
  const float heroEta = lobe.a.v[0];  // the direction is chosen with lane 0's IOR
  if (!(heroEta > 0.0f) || !std::isfinite(heroEta)) return std::nullopt;
  const float reflectance = fresnelDielectric(wo.z, heroEta);
  const float transmittance = 1.0f - reflectance;

  BsdfSample s;
  s.specular = true;
  // R + T = 1, so the reflection probability R / (R + T) is R itself.
  if (uc < reflectance) {
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.pdfW = reflectance;
    const float invCos = 1.0f / cosO;
    if (lobe.etaVaries) {
      // The mirror direction is the same for every wavelength, so every lane keeps its own
      // Fresnel value: lane i's estimate R_i / R_0 is unbiased (R_0 > 0 when reflection is
      // chosen). Not dispersive.
      for (int i = 0; i < kLanes; ++i) s.f.v[i] = lobe.weight.v[i] * fresnelDielectric(wo.z, lobe.a.v[i]) * invCos;
    } else {
      s.f = lobe.weight * (reflectance * invCos);
    }
    return s;
  }

  // Refraction (Snell's law) into the other side. etaRel = n_transmitted / n_incident.
  const bool entering = wo.z > 0.0f;
  const float etaRel = entering ? heroEta : 1.0f / heroEta;
  Vec3 wi;
  if (etaRel == 1.0f) {
    wi = -wo;  // index-matched: straight through, exactly
  } else {
    const float sin2T = std::max(0.0f, 1.0f - cosO * cosO) / (etaRel * etaRel);
    if (!(sin2T < 1.0f)) return std::nullopt;  // total internal reflection (R = 1 chose reflection already)
    const float cosT = std::sqrt(1.0f - sin2T);
    const float towardWo = entering ? 1.0f : -1.0f;  // the normal on wo's side
    wi = -wo / etaRel + Vec3(0.0f, 0.0f, towardWo * (cosO / etaRel - cosT));
  }
  const float cosI = std::fabs(wi.z);
  if (!(cosI >= kMinCosTheta)) return std::nullopt;
  s.wi = wi;
  s.pdfW = transmittance;
  s.transmission = true;
  s.etaScale = etaRel;
  // Radiance is compressed into the smaller solid angle of the denser side (Veach 5.2);
  // importance is not.
  const float modeScale = mode == TransportMode::Radiance ? 1.0f / (etaRel * etaRel) : 1.0f;
  s.f = lobe.weight * (Spectrum(1.0f) - lobe.b) * (transmittance * modeScale / cosI);  // b: the tint's loss
  if (lobe.etaVaries) {
    // Only the hero wavelength really refracts into wi: the other lanes would refract
    // elsewhere, so their values are zeroed here and the integrator decides (bsdf.h).
    for (int i = 1; i < kLanes; ++i) s.f.v[i] = 0.0f;
    s.dispersive = true;
  }
  return s;
}

// ---- Smooth conductor: mirror reflection with the complex Fresnel reflectance.

std::optional<BsdfSample> conductorSample(const Lobe& lobe, const Vec3& wo) {
  const float cosO = std::fabs(wo.z);
  if (!(cosO >= kMinCosTheta)) return std::nullopt;
  BsdfSample s;
  s.specular = true;
  s.wi = Vec3(-wo.x, -wo.y, wo.z);
  s.pdfW = 1.0f;
  s.f = lobe.weight * fresnelConductor(cosO, lobe.a, lobe.b) * (1.0f / cosO);
  return s;
}

}  // namespace

Spectrum lobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  switch (lobe.kind) {
    case LobeKind::Lambertian:
      return lambertianEval(lobe, wo, wi);
    case LobeKind::SmoothDielectric:
    case LobeKind::SmoothConductor:
    case LobeKind::ThinDielectric:
      return Spectrum();  // Dirac lobes: no density to evaluate
    case LobeKind::GlossyReflection:
    case LobeKind::GlossyDielectric:
      return glossyLobeEval(lobe, wo, wi, mode);
    case LobeKind::RoughConductor:
      return roughConductorEval(lobe, wo, wi);
    case LobeKind::RoughDielectric:
      return roughDielectricEval(lobe, wo, wi, mode);
    case LobeKind::RoughThinDielectric:
      return roughThinDielectricEval(lobe, wo, wi);
    case LobeKind::Sheen:
    case LobeKind::LambertianUnderSheen:
      return sheenLobeEval(lobe, wo, wi);
  }
  return Spectrum();
}

float lobePdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  switch (lobe.kind) {
    case LobeKind::Lambertian:
      return lambertianPdf(wo, wi);
    case LobeKind::SmoothDielectric:
    case LobeKind::SmoothConductor:
    case LobeKind::ThinDielectric:
      return 0.0f;
    case LobeKind::GlossyReflection:
    case LobeKind::GlossyDielectric:
      return glossyLobePdf(lobe, wo, wi, mode);
    case LobeKind::RoughConductor:
      return roughConductorPdf(lobe, wo, wi);
    case LobeKind::RoughDielectric:
      return roughDielectricPdfForLane(lobe, wo, wi, 0);
    case LobeKind::RoughThinDielectric:
      return roughThinDielectricPdf(lobe, wo, wi);
    case LobeKind::Sheen:
    case LobeKind::LambertianUnderSheen:
      return sheenLobePdf(wo, wi);
  }
  return 0.0f;
}

float lobePdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode, int lane) {
  if (!lobe.etaVaries || lane == 0) return lobePdf(lobe, wo, wi, mode);
  switch (lobe.kind) {
    case LobeKind::GlossyDielectric:
      return glossyLobePdfForLane(lobe, wo, wi, mode, lane);
    case LobeKind::RoughDielectric:
      return roughDielectricPdfForLane(lobe, wo, wi, lane);
    default:
      return lobePdf(lobe, wo, wi, mode);
  }
}

std::optional<BsdfSample> lobeSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode) {
  switch (lobe.kind) {
    case LobeKind::Lambertian:
      return lambertianSample(lobe, wo, u2);
    case LobeKind::SmoothDielectric:
      return dielectricSample(lobe, wo, uc, mode);
    case LobeKind::SmoothConductor:
      return conductorSample(lobe, wo);
    case LobeKind::GlossyReflection:
    case LobeKind::GlossyDielectric:
      return glossyLobeSample(lobe, wo, uc, u2, mode);
    case LobeKind::RoughConductor:
      return roughConductorSample(lobe, wo, u2);
    case LobeKind::RoughDielectric:
      return roughDielectricSample(lobe, wo, uc, u2, mode);
    case LobeKind::ThinDielectric:
      return thinDielectricSample(lobe, wo, uc);
    case LobeKind::RoughThinDielectric:
      return roughThinDielectricSample(lobe, wo, uc, u2);
    case LobeKind::Sheen:
    case LobeKind::LambertianUnderSheen:
      return sheenLobeSample(lobe, wo, u2);
  }
  return std::nullopt;
}

}  // namespace tex::render
