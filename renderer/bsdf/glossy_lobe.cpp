// The glossy model's lobes (docs/glossy-model.md). In the projected-disk plane of wi (where
// |cos theta_i| dw_i = dA), the lobe is the planar kernel p(q) of the tangential momentum
// mismatch q = eta_o wo_t + eta_i wi_t (reflection: eta_o = eta_i = 1, so q = wo_t + wi_t),
// divided by the symmetric max(M(wo), M(wi)), where M(w) is the share of w's kernel that lands
// inside the disk of the medium it scatters into. Then:
//  - reciprocity is exact (q, the max and the symmetric Fresnel factors are symmetric);
//  - albedo <= weight exactly (f |cos| <= weight p(q) / M(wo), whose integral is weight);
//  - sampling is exact: draw q from the kernel around the ideal point, lift to the
//    hemisphere; points outside the disk (below the horizon) give no sample, so
//    pdfW = eta_i^2 p(q) |cos theta_i| is the exact density of the returned samples.
// GlossyReflection adds the reciprocal compensation lobe (Kulla & Conty 2017)
// f_ms = (1 - E(wo)) (1 - E(wi)) / (pi (1 - E_avg)) with E tabulated (glossy_albedo.h), which
// returns the energy the max() loses near grazing; sampled cosine-weighted with probability
// 1 - E(wo), the glossy lobe with E(wo).
#include "renderer/bsdf/glossy_lobe.h"

#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/glossy_albedo.h"
#include "renderer/bsdf/glossy_kernel.h"
#include "renderer/core/warp.h"

namespace tex::render {
namespace {

using glossy::kernelDensity;
using glossy::kernelMassInDisk;

constexpr double kTwoPiD = 6.28318530717958647692;

bool degenerate(const Vec3& w) { return !(std::fabs(w.z) >= kMinCosTheta) || !std::isfinite(w.x + w.y); }
bool validExponent(float n) { return n >= 0.0f && std::isfinite(n); }
bool validEta(float eta) { return eta > 0.0f && std::isfinite(eta); }

double tangentialLength(const Vec3& w) { return std::hypot(double(w.x), double(w.y)); }

// kernelMassInDisk for wo's side, remembered per thread: a path vertex evaluates and samples
// the same wo many times (NEE, BSDF sample, MIS), and M(wo) costs a 32-point quadrature.
double massForOutgoing(double n, double d, double R) {
  thread_local double lastN = -1.0, lastD = -1.0, lastR = -1.0, lastM = 0.0;
  if (n != lastN || d != lastD || R != lastR) {
    lastM = kernelMassInDisk(n, d, R);
    lastN = n, lastD = d, lastR = R;
  }
  return lastM;
}

// Reflection lobe in the disk plane: p(wo_t + wi_t) / max(M(wo), M(wi)), M over the unit disk.
double reflectionLobe(double n, const Vec3& wo, const Vec3& wi) {
  const double qx = double(wo.x) + double(wi.x), qy = double(wo.y) + double(wi.y);
  const double p = kernelDensity(n, qx * qx + qy * qy);
  if (p == 0.0) return 0.0;
  // M decreases as the kernel's centre moves away from the disk's (Anderson's theorem: a
  // symmetric unimodal density, a symmetric convex set), so when wi is further out than wo the
  // max is M(wo), already known: the quadrature for M(wi) is needed only when wi is closer in.
  const double dO = tangentialLength(wo), dI = tangentialLength(wi);
  const double mO = massForOutgoing(n, dO, 1.0);
  const double m = dI >= dO ? mO : std::max(mO, kernelMassInDisk(n, dI, 1.0));
  return m > 0.0 ? p / m : 0.0;
}

// Refraction lobe in the momentum plane: p(etaO wo_t + etaI wi_t) / max(M(wo), M(wi)), where
// wo's kernel must land in the disk of radius etaI (wi's medium) and vice versa.
double transmissionLobe(double n, const Vec3& wo, const Vec3& wi, double etaO, double etaI) {
  const double qx = etaO * wo.x + etaI * wi.x, qy = etaO * wo.y + etaI * wi.y;
  const double p = kernelDensity(n, qx * qx + qy * qy);
  if (p == 0.0) return 0.0;
  const double m = std::max(massForOutgoing(n, etaO * tangentialLength(wo), etaI),
                            kernelMassInDisk(n, etaI * tangentialLength(wi), etaO));
  return m > 0.0 ? p / m : 0.0;
}

// The energy-compensation lobe of GlossyReflection (symmetric in wo, wi).
double compensation(double n, const Vec3& wo, const Vec3& wi) {
  return glossy::compensationValue(n, std::fabs(double(wo.z)), std::fabs(double(wi.z)));
}

// GlossyReflection's sampling density: the glossy lobe's kernel with probability E(wo), the
// cosine lobe with 1 - E(wo) (E = the tabulated glossy albedo, 1 where nothing is lost).
double reflectionPdf(double n, const Vec3& wo, const Vec3& wi) {
  const double cosI = std::fabs(double(wi.z));
  const double pickCompensation = 1.0 - glossy::tabulatedAlbedo(n, std::fabs(double(wo.z)));
  const double qx = double(wo.x) + wi.x, qy = double(wo.y) + wi.y;
  return (1.0 - pickCompensation) * kernelDensity(n, qx * qx + qy * qy) * cosI + pickCompensation * cosI / M_PI;
}

// Sides of the interface for a relative IOR eta (inside over outside) seen from wo.
struct Indices {
  double etaO, etaI;  // index on wo's side and on the transmitted side
};
Indices indicesFor(const Vec3& wo, float eta) { return wo.z > 0.0f ? Indices{1.0, eta} : Indices{eta, 1.0}; }

// One lane of GlossyDielectric's value (without the weight).
double dielectricValue(double n, const Vec3& wo, const Vec3& wi, float eta, TransportMode mode) {
  if (!validEta(eta)) return 0.0;
  const double fo = fresnelDielectric(wo.z, eta), fi = fresnelDielectric(wi.z, eta);
  if (sameHemisphere(wo, wi)) return std::min(fo, fi) * reflectionLobe(n, wo, wi);
  const Indices ix = indicesFor(wo, eta);
  // Importance: eta_i^2 (flux conserved); Radiance: eta_o^2 (radiance / eta^2 invariant).
  const double modeScale = mode == TransportMode::Importance ? ix.etaI * ix.etaI : ix.etaO * ix.etaO;
  return std::min(1.0 - fo, 1.0 - fi) * modeScale * transmissionLobe(n, wo, wi, ix.etaO, ix.etaI);
}

// Density of sampling wi with lane IOR eta (GlossyDielectric) or of the reflection lobe.
double dielectricPdf(double n, const Vec3& wo, const Vec3& wi, float eta) {
  if (!validEta(eta)) return 0.0;
  const double fo = fresnelDielectric(wo.z, eta);
  const double cosI = std::fabs(double(wi.z));
  if (sameHemisphere(wo, wi)) {
    const double qx = double(wo.x) + wi.x, qy = double(wo.y) + wi.y;
    return fo * kernelDensity(n, qx * qx + qy * qy) * cosI;
  }
  const Indices ix = indicesFor(wo, eta);
  const double qx = ix.etaO * wo.x + ix.etaI * wi.x, qy = ix.etaO * wo.y + ix.etaI * wi.y;
  return (1.0 - fo) * ix.etaI * ix.etaI * kernelDensity(n, qx * qx + qy * qy) * cosI;
}

// Draws a point of the kernel around `centre` (u2 -> radius, angle) and divides it by `scale`
// (the momentum of the medium scattered into); nothing when it lands outside the unit disk.
std::optional<Vec3> liftKernelSample(double n, double cx, double cy, double scale, Vec2 u2, float zSign) {
  const double r = glossy::sampleKernelRadius(n, 1.0 - double(u2.x));  // 1 - u in (0, 1]
  const double phi = kTwoPiD * double(u2.y);
  const double x = (cx + r * std::cos(phi)) / scale, y = (cy + r * std::sin(phi)) / scale;
  const double t2 = x * x + y * y;
  if (!(t2 < 1.0)) return std::nullopt;  // below the horizon: no sample (pdf accounts for it)
  const Vec3 wi(float(x), float(y), float(zSign * std::sqrt(1.0 - t2)));
  if (degenerate(wi)) return std::nullopt;
  return wi;
}

}  // namespace

Spectrum glossyLobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  if (degenerate(wo) || degenerate(wi) || !validExponent(lobe.exponent)) return Spectrum();
  const double n = lobe.exponent;
  if (lobe.kind == LobeKind::GlossyReflection) {
    if (!sameHemisphere(wo, wi)) return Spectrum();
    return lobe.weight * float(reflectionLobe(n, wo, wi) + compensation(n, wo, wi));
  }
  Spectrum f;
  if (!lobe.etaVaries) {
    const float v = float(dielectricValue(n, wo, wi, lobe.a.v[0], mode));
    return lobe.weight * v;
  }
  for (int i = 0; i < kLanes; ++i)
    if (lobe.weight.v[i] != 0.0f) f.v[i] = lobe.weight.v[i] * float(dielectricValue(n, wo, wi, lobe.a.v[i], mode));
  return f;
}

float glossyLobePdfForLane(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode, int lane) {
  if (degenerate(wo) || degenerate(wi) || !validExponent(lobe.exponent) || lane < 0 || lane >= kLanes) return 0.0f;
  const double n = lobe.exponent;
  if (lobe.kind == LobeKind::GlossyReflection) {
    if (!sameHemisphere(wo, wi)) return 0.0f;
    return float(reflectionPdf(n, wo, wi));
  }
  return float(dielectricPdf(n, wo, wi, lobe.a.v[lobe.etaVaries ? lane : 0]));
}

float glossyLobePdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  return glossyLobePdfForLane(lobe, wo, wi, mode, 0);
}

std::optional<BsdfSample> glossyLobeSample(const Lobe& lobe, const Vec3& wo, float uc, Vec2 u2, TransportMode mode) {
  if (degenerate(wo) || !validExponent(lobe.exponent)) return std::nullopt;
  const double n = lobe.exponent;
  const float side = wo.z > 0.0f ? 1.0f : -1.0f;
  bool transmit = false;
  std::optional<Vec3> wi;
  float etaScale = 1.0f;
  if (lobe.kind == LobeKind::GlossyReflection) {
    const double pickCompensation = 1.0 - glossy::tabulatedAlbedo(n, std::fabs(double(wo.z)));
    if (double(uc) < pickCompensation) {
      Vec3 w = sampleCosineHemisphere(u2);
      w.z *= side;
      if (!degenerate(w)) wi = w;
    } else {
      wi = liftKernelSample(n, -double(wo.x), -double(wo.y), 1.0, u2, side);
    }
  } else {
    const float heroEta = lobe.a.v[0];
    if (!validEta(heroEta)) return std::nullopt;
    const double fo = fresnelDielectric(wo.z, heroEta);
    if (uc < fo) {
      wi = liftKernelSample(n, -double(wo.x), -double(wo.y), 1.0, u2, side);
    } else {
      const Indices ix = indicesFor(wo, heroEta);
      wi = liftKernelSample(n, -ix.etaO * wo.x, -ix.etaO * wo.y, ix.etaI, u2, -side);
      transmit = true;
      etaScale = float(ix.etaI / ix.etaO);
    }
  }
  if (!wi) return std::nullopt;
  BsdfSample s;
  s.wi = *wi;
  s.pdfW = glossyLobePdf(lobe, wo, s.wi, mode);
  if (!(s.pdfW > 0.0f) || !std::isfinite(s.pdfW)) return std::nullopt;
  s.f = glossyLobeEval(lobe, wo, s.wi, mode);
  s.transmission = transmit;
  s.etaScale = etaScale;
  // Refraction by the hero's IOR: the other lanes' lobes are elsewhere (their own values at
  // wi are in f; spectral MIS needs glossyLobePdfForLane). Reflection is not dispersive.
  s.dispersive = transmit && lobe.etaVaries;
  return s;
}

float glossyReflectionAlbedo(float exponent, float cosThetaO) {
  // Glossy part by quadrature; the compensation lobe's albedo is exactly 1 - E_table(wo)
  // (glossy_albedo.h: E_avg is the exact average of the table's interpolant).
  if (!validExponent(exponent) || !(cosThetaO >= 0.0f) || cosThetaO > 1.0f) return 0.0f;
  const double e = glossy::reflectionAlbedoQuadrature(exponent, cosThetaO);
  const double eTable = glossy::tabulatedAlbedo(exponent, cosThetaO);
  const double compensated = eTable < 1.0 && glossy::tabulatedAverageAlbedo(exponent) < 1.0 ? 1.0 - eTable : 0.0;
  return float(e + compensated);
}

}  // namespace tex::render
