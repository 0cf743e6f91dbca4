// Rough dielectric: GGX reflection and transmission through one interface (Walter et al. 2007;
// pbrt-v4 section 9.7). eta = lobe.a per lane (inside over outside), alpha = lobe.roughness;
// transmission is filtered by the tint 1 - lobe.b (glTF's coloured glass), reflection is not.
//  - Generalized half vector wm ~ wo + eta_p wi (eta_p = 1 for reflection, else the relative IOR
//    of wi's side over wo's), turned to the upper side; back-facing configurations have f = 0.
//  - Transmission: f = D G (1 - F) |wi.wm| |wo.wm| / (|cos_i| |cos_o| (wi.wm + wo.wm / eta_p)^2),
//    divided by eta_p^2 in Radiance mode only (Veach 1997, 5.2).
//  - Sampling (hero lane 0): a visible normal (Heitz 2018), reflect with probability F(wo.wm)
//    else refract; pdf = D_wo(wm) F / (4 |wo.wm|) or D_wo(wm) (1 - F) |wi.wm| / (wi.wm + wo.wm / eta_p)^2.
//  - etaVaries: lanes 1.. carry their own f_i(wo, wi) at the hero's wi (nonzero: every lane has
//    a density there), and the sample is `dispersive` (the density differs between lanes);
//    roughDielectricPdfForLane gives each lane's density for spectral MIS.
//  - eta = 1 (index-matched): no interface, the light passes straight through (a Dirac event).
//  - The transmitted density jumps to 0 on the ring wi.z = -wo.z / eta_p, where wm reaches the
//    microfacet horizon (D = alpha^2 / pi there, not 0); near eta = 1 the ring passes next to
//    the lobe's peak at wi = -wo (dwm/dwi ~ 1 / (eta - 1)^2), so quadratures must split there.
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/microfacet.h"

namespace tex::render {
namespace {

bool indexMatched(float eta) { return std::fabs(eta - 1.0f) < 1e-4f; }
bool validEta(float eta) { return eta > 0.0f && std::isfinite(eta); }

struct HalfVector {
  Vec3 wm;
  float etaP = 1;  // 1 for reflection; the relative IOR across the interface for transmission
  bool reflect = true;
};

// The generalized half vector of a direction pair for IOR eta (false when degenerate or back-facing).
bool generalizedHalfVector(const Vec3& wo, const Vec3& wi, float eta, HalfVector& hv) {
  if (!(std::fabs(wo.z) >= kMinCosTheta) || !(std::fabs(wi.z) >= kMinCosTheta)) return false;
  hv.reflect = wo.z * wi.z > 0.0f;
  hv.etaP = hv.reflect ? 1.0f : (wo.z > 0.0f ? eta : 1.0f / eta);
  Vec3 wm = wi * hv.etaP + wo;
  const float len2 = lengthSquared(wm);
  if (!(len2 > 1e-20f)) return false;
  wm /= std::sqrt(len2);
  if (wm.z < 0.0f) wm = -wm;
  if (!(wm.z > 0.0f)) return false;
  // Each direction must see the microfacet from the side it is on.
  if (dot3(wm, wi) * wi.z <= 0.0f || dot3(wm, wo) * wo.z <= 0.0f) return false;
  hv.wm = wm;
  return true;
}

// f for unit weight with IOR eta.
float roughDielectricValue(const Vec3& wo, const Vec3& wi, float eta, const GgxAlpha& alpha, TransportMode mode) {
  if (!validEta(eta) || indexMatched(eta)) return 0.0f;  // index-matched: only the Dirac pass-through
  HalfVector hv;
  if (!generalizedHalfVector(wo, wi, eta, hv)) return 0.0f;
  const float cosOm = dot3(wo, hv.wm), cosIm = dot3(wi, hv.wm);
  const float fresnel = fresnelDielectric(cosOm, eta);
  const float dg = ggxD(hv.wm, alpha) * ggxG(wo, wi, alpha);
  float f;
  if (hv.reflect) {
    f = dg * fresnel / (4.0f * std::fabs(wo.z * wi.z));
  } else {
    const float denom = cosIm + cosOm / hv.etaP;
    const float denom2 = denom * denom * std::fabs(wo.z * wi.z);
    if (!(denom2 > 0.0f)) return 0.0f;
    f = dg * (1.0f - fresnel) * std::fabs(cosIm * cosOm) / denom2;
    if (mode == TransportMode::Radiance) f /= hv.etaP * hv.etaP;
  }
  return std::isfinite(f) ? f : 0.0f;
}

float roughDielectricDensity(const Vec3& wo, const Vec3& wi, float eta, const GgxAlpha& alpha) {
  if (!validEta(eta) || indexMatched(eta)) return 0.0f;
  HalfVector hv;
  if (!generalizedHalfVector(wo, wi, eta, hv)) return 0.0f;
  const float cosOm = dot3(wo, hv.wm), cosIm = dot3(wi, hv.wm);
  const float reflectance = fresnelDielectric(cosOm, eta);
  const float visibleD = ggxVisibleD(wo, hv.wm, alpha);
  float pdfW;
  if (hv.reflect) {
    pdfW = visibleD / (4.0f * std::fabs(cosOm)) * reflectance;
  } else {
    const float denom = cosIm + cosOm / hv.etaP;
    if (!(denom * denom > 0.0f)) return 0.0f;
    pdfW = visibleD * std::fabs(cosIm) / (denom * denom) * (1.0f - reflectance);  // dwm/dwi (Walter eq. 17)
  }
  return std::isfinite(pdfW) ? pdfW : 0.0f;
}

// Refraction of w through a facet with normal n (n.z > 0) for eta = inside over outside.
bool refractThrough(const Vec3& w, Vec3 n, float eta, Vec3& wt) {
  float cosI = dot3(n, w);
  float etaRel = eta;  // transmitted over incident
  if (cosI < 0.0f) {
    etaRel = 1.0f / eta;
    cosI = -cosI;
    n = -n;
  }
  const float sin2T = std::max(0.0f, 1.0f - cosI * cosI) / (etaRel * etaRel);
  if (!(sin2T < 1.0f)) return false;
  const float cosT = std::sqrt(1.0f - sin2T);
  wt = -w / etaRel + n * (cosI / etaRel - cosT);
  return true;
}

}  // namespace

Spectrum roughDielectricEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  const GgxAlpha alpha = ggxAlphaOf(lobe);
  // Transmission is filtered by the tint (b = 1 - tint), reflection never.
  const Spectrum weight = wo.z * wi.z < 0.0f ? lobe.weight * (Spectrum(1.0f) - lobe.b) : lobe.weight;
  if (!lobe.etaVaries) return weight * roughDielectricValue(wo, wi, lobe.a.v[0], alpha, mode);
  Spectrum f;
  for (int i = 0; i < kLanes; ++i)
    if (weight.v[i] != 0.0f) f.v[i] = weight.v[i] * roughDielectricValue(wo, wi, lobe.a.v[i], alpha, mode);
  return f;
}

float roughDielectricPdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, int lane) {
  if (lane < 0 || lane >= kLanes) return 0.0f;
  const float eta = lobe.etaVaries ? lobe.a.v[lane] : lobe.a.v[0];
  return roughDielectricDensity(wo, wi, eta, ggxAlphaOf(lobe));
}

std::optional<BsdfSample> roughDielectricSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode) {
  if (!(std::fabs(wo.z) >= kMinCosTheta)) return std::nullopt;
  const float heroEta = lobe.a.v[0];
  if (!validEta(heroEta)) return std::nullopt;
  BsdfSample s;
  if (indexMatched(heroEta)) {  // no interface: straight through, as the smooth dielectric does
    s.wi = -wo;
    s.specular = true;
    s.transmission = true;
    s.pdfW = 1.0f;
    const float invCos = 1.0f / std::fabs(wo.z);
    for (int i = 0; i < kLanes; ++i)
      s.f.v[i] = (!lobe.etaVaries || indexMatched(lobe.a.v[i])) ? lobe.weight.v[i] * (1.0f - lobe.b.v[i]) * invCos : 0.0f;
    s.dispersive = lobe.etaVaries;
    return s;
  }
  const GgxAlpha alpha = ggxAlphaOf(lobe);
  const Vec3 wm = ggxSampleVisibleNormal(wo, alpha, u2);
  const float reflectance = fresnelDielectric(dot3(wo, wm), heroEta);
  Vec3 wi;
  if (uc < reflectance) {
    wi = reflect(wo, wm);
    if (!(wi.z * wo.z > 0.0f)) return std::nullopt;
  } else {
    if (!refractThrough(wo, wm, heroEta, wi)) return std::nullopt;
    if (!(wi.z * wo.z < 0.0f)) return std::nullopt;
    s.transmission = true;
    s.etaScale = wo.z > 0.0f ? heroEta : 1.0f / heroEta;
  }
  const float len2 = lengthSquared(wi);
  if (!(len2 > 0.0f)) return std::nullopt;
  wi /= std::sqrt(len2);
  s.wi = wi;
  s.pdfW = roughDielectricDensity(wo, wi, heroEta, alpha);  // the expression lobePdf evaluates
  if (!(s.pdfW > 0.0f)) return std::nullopt;
  s.f = roughDielectricEval(lobe, wo, wi, mode);
  s.dispersive = lobe.etaVaries;
  return s;
}

}  // namespace tex::render
