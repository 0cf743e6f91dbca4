// The glossy model's lobes (docs/glossy-model.md). In the projected-disk plane of wi (where
// |cos theta_i| dw_i = dA), the lobe is the planar kernel p(q) of the tangential momentum
// mismatch q = eta_o wo_t + eta_i wi_t (reflection off GlossyReflection: q = wo_t + wi_t),
// divided by a normalisation symmetric in (wo, wi): the max of both directions' own. Then:
//  - reciprocity is exact (q, the max and the symmetric Fresnel weights are symmetric);
//  - albedo <= weight exactly (f |cos| <= weight p(q) / norm(wo), whose integral is weight);
//  - sampling is exact: draw q from the kernel around the ideal point, lift to the
//    hemisphere; points no direction has (below the horizon) give no sample, so the pdf is
//    the exact density of the returned samples.
// GlossyReflection: norm = M, the share of the kernel inside the unit disk (from the mass table,
// glossy_mass_table.h; by quadrature below its exponents); plus
// the reciprocal compensation lobe (Kulla & Conty 2017) f_ms = (1 - E(wo)) (1 - E(wi)) /
// (pi (1 - E_avg)) with E tabulated (glossy_albedo.h), which returns the energy the max()
// loses near grazing; sampled cosine-weighted with probability 1 - E(wo), the glossy lobe with
// E(wo). GlossyDielectric: reflection and refraction share q in the momentum plane, weighted by
// the mean Fresnel reflectance F^ of both directions and 1 - F^; norm = N, the weighted share
// of the kernel that scatters somewhere, from tabulated masses (glossy_mass_table.h).
#include "renderer/bsdf/glossy_lobe.h"

#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/glossy_albedo.h"
#include "renderer/bsdf/glossy_kernel.h"
#include "renderer/bsdf/glossy_mass_table.h"
#include "renderer/core/warp.h"

namespace tex::render {
namespace {

using glossy::kernelDensity;

constexpr double kTwoPiD = 6.28318530717958647692;

bool degenerate(const Vec3& w) { return !(std::fabs(w.z) >= kMinCosTheta) || !std::isfinite(w.x + w.y); }
bool validExponent(float n) { return n >= 0.0f && std::isfinite(n); }
bool validEta(float eta) { return eta > 0.0f && std::isfinite(eta); }

double tangentialLength(const Vec3& w) { return std::hypot(double(w.x), double(w.y)); }

// The kernel's mass in the unit disk from the table (glossy_mass_table.h: an upper bound within
// about 2.5e-5, 7e-5 below n = 63, so the lobe's albedo stays <= 1; the quadrature itself below
// n = 7). Round 16: the reflection lobe had run the 32-point quadrature (an acos, sincos, log and
// expm1 per node) for M(wi) at every evaluation and for every new wo, 70 % of a render of a
// glossy() sphere (a GGX conductor's rays were 5x as fast).
double massInUnitDisk(double n, double d) { return glossy::tabulatedMassInDisk(n, d, 1.0); }

// max(M(wo), M(wi)) for the reflection lobe. Below the table's exponents (n < 7) M is the exact
// quadrature, which falls as the kernel's centre moves out (Anderson's theorem: a symmetric
// unimodal density, a symmetric convex set), so the max is M at the smaller distance: one
// quadrature, remembered per thread for the vertex's repeated evaluations.
double reflectionMass(double n, double dO, double dI) {
  if (glossy::massTableCovers(n, 1.0)) return std::max(massInUnitDisk(n, dO), massInUnitDisk(n, dI));
  const double d = std::min(dO, dI);
  thread_local double lastN = -1.0, lastD = -1.0, lastM = 0.0;
  if (n != lastN || d != lastD) lastM = glossy::kernelMassInDisk(n, d, 1.0), lastN = n, lastD = d;
  return lastM;
}

// Reflection lobe in the disk plane: p(wo_t + wi_t) / max(M(wo), M(wi)), M over the unit disk.
double reflectionLobe(double n, const Vec3& wo, const Vec3& wi) {
  const double qx = double(wo.x) + double(wi.x), qy = double(wo.y) + double(wi.y);
  const double p = kernelDensity(n, qx * qx + qy * qy);
  if (p == 0.0) return 0.0;
  // Both masses from the table: its interpolant need not fall exactly as the kernel's centre
  // moves out, and the max of both keeps the lobe reciprocal.
  const double m = reflectionMass(n, tangentialLength(wo), tangentialLength(wi));
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

// GlossyDielectric (docs/glossy-model.md, "GlossyDielectric"). Everything lives in the plane of
// tangential momenta k = eta_side w_t, which the interface conserves: the kernel draws
// q = a + b, a = eta_o wo_t, b = the momentum of wi; reflection and refraction share q (the
// reflected wi has momentum b on wo's side, the refracted one on the other side), and the
// event weights F^ and 1 - F^ at that q sum to 1 wherever both directions exist.

// The index on w's side and on the other side of the interface (relative IOR eta inside).
struct Sides {
  double own, other;
};
Sides sidesOf(const Vec3& w, float eta) { return w.z > 0.0f ? Sides{1.0, eta} : Sides{eta, 1.0}; }

// Fresnel reflectance at tangential momentum k: the outside cosine is sqrt(1 - k^2); k >= 1
// exists only inside (eta > 1) and is totally reflected.
double fresnelAtMomentum(double k, float eta) {
  if (!(k < 1.0)) return 1.0;
  return fresnelDielectric(float(std::sqrt((1.0 - k) * (1.0 + k))), eta);
}

// The symmetric Fresnel weight of a pair: the mean of both directions' reflectances.
double meanFresnel(double kO, double kI, float eta) { return 0.5 * (fresnelAtMomentum(kO, eta) + fresnelAtMomentum(kI, eta)); }

// N(w): the weighted share of w's kernel that scatters somewhere. Momenta inside the smaller
// of the two disks (radii = the two indices) have both events, weights F^ + (1 - F^) = 1; those
// between the radii have one event only: reflection (w on the denser side; weight
// F^ = (F(w) + 1) / 2, the far direction being totally reflected) or refraction (w on the rarer
// side; weight 1 - F^ = (1 - F(w)) / 2). Upper bound of the exact value (table masses are).
double dielectricNorm(double n, double k, Sides s, double fresnelOfW) {
  const double rLo = std::min(s.own, s.other), rHi = std::max(s.own, s.other);
  const double mLo = glossy::tabulatedMassInDisk(n, k, rLo);
  if (rLo == rHi) return mLo;
  const double mHi = glossy::tabulatedMassInDisk(n, k, rHi);
  const double share = s.own > s.other ? 0.5 * (1.0 + fresnelOfW) : 0.5 * (1.0 - fresnelOfW);
  return mLo + share * (mHi - mLo);
}

// The pair's geometry: sides, momenta, kernel density.
struct DielectricPair {
  bool reflect;
  Sides sO;
  double etaI;  // index on wi's side
  double kO, kI, density;
};
DielectricPair pairOf(double n, const Vec3& wo, const Vec3& wi, float eta) {
  DielectricPair g;
  g.reflect = sameHemisphere(wo, wi);
  g.sO = sidesOf(wo, eta);
  g.etaI = g.reflect ? g.sO.own : g.sO.other;
  const double qx = g.sO.own * wo.x + g.etaI * wi.x, qy = g.sO.own * wo.y + g.etaI * wi.y;
  g.kO = g.sO.own * tangentialLength(wo);
  g.kI = g.etaI * tangentialLength(wi);
  g.density = kernelDensity(n, qx * qx + qy * qy);
  return g;
}

// One lane of GlossyDielectric's value (without the weight):
//   W s p(q) / max(N(wo), N(wi)),  W = F^ (reflection) or 1 - F^ (refraction),
// s = eta_i^2 (Importance) or eta_o^2 (Radiance): the planar density in momentum becomes one
// in wi_t (|cos| dw = dA(wi_t) = dA(b) / eta_i^2); radiance / eta^2 is invariant.
double dielectricValue(double n, const Vec3& wo, const Vec3& wi, float eta, TransportMode mode) {
  if (!validEta(eta)) return 0.0;
  const DielectricPair g = pairOf(n, wo, wi, eta);
  if (g.density == 0.0) return 0.0;
  const double fO = fresnelAtMomentum(g.kO, eta), fI = fresnelAtMomentum(g.kI, eta);
  const double fMean = 0.5 * (fO + fI);
  const double w = g.reflect ? fMean : 1.0 - fMean;
  if (!(w > 0.0)) return 0.0;
  const double norm = std::max(dielectricNorm(n, g.kO, g.sO, fO), dielectricNorm(n, g.kI, sidesOf(wi, eta), fI));
  if (!(norm > 0.0)) return 0.0;
  const double modeScale = g.reflect || mode == TransportMode::Radiance ? g.sO.own * g.sO.own : g.etaI * g.etaI;
  return w * modeScale * g.density / norm;
}

// Density of sampling wi with lane IOR eta: q from the kernel, then reflection with
// probability F^, refraction with 1 - F^ (no sample when the chosen event has no direction
// with that momentum): the event's probability is its weight W, so f |cos| / pdf = s / eta_i^2
// / max(N(wo), N(wi)), and the density is continuous up to the horizon.
double dielectricPdf(double n, const Vec3& wo, const Vec3& wi, float eta) {
  if (!validEta(eta)) return 0.0;
  const DielectricPair g = pairOf(n, wo, wi, eta);
  if (g.density == 0.0) return 0.0;
  const double fMean = meanFresnel(g.kO, g.kI, eta);
  return (g.reflect ? fMean : 1.0 - fMean) * g.etaI * g.etaI * g.density * std::fabs(double(wi.z));
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
  bool transmit = false, dispersive = false;
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
    // q around 0 from the kernel, b = q - a the scattered momentum, then the event.
    const Sides sO = sidesOf(wo, heroEta);
    const double ax = sO.own * wo.x, ay = sO.own * wo.y;
    const double r = glossy::sampleKernelRadius(n, 1.0 - double(u2.x)), phi = kTwoPiD * double(u2.y);
    const double bx = r * std::cos(phi) - ax, by = r * std::sin(phi) - ay;
    const double kB = std::hypot(bx, by);
    transmit = double(uc) >= meanFresnel(sO.own * tangentialLength(wo), kB, heroEta);
    if (!(kB < (transmit ? sO.other : sO.own))) return std::nullopt;  // no such direction
    const double etaI = transmit ? sO.other : sO.own;
    const double x = bx / etaI, y = by / etaI, t2 = x * x + y * y;
    if (!(t2 < 1.0)) return std::nullopt;
    const Vec3 w(float(x), float(y), float((transmit ? -side : side) * std::sqrt(1.0 - t2)));
    if (degenerate(w)) return std::nullopt;
    wi = w;
    if (transmit) etaScale = float(sO.other / sO.own);
    // Lanes differ in density unless the event is reflection outside (same q plane for all
    // lanes, the hero's event probability > 0 wherever any lane's value is).
    dispersive = lobe.etaVaries && (transmit || wo.z < 0.0f);
  }
  if (!wi) return std::nullopt;
  BsdfSample s;
  s.wi = *wi;
  s.pdfW = glossyLobePdf(lobe, wo, s.wi, mode);
  if (!(s.pdfW > 0.0f) || !std::isfinite(s.pdfW)) return std::nullopt;
  s.f = glossyLobeEval(lobe, wo, s.wi, mode);
  s.transmission = transmit;
  s.etaScale = etaScale;
  // Chosen with the hero's IOR: the other lanes' own values at wi are in f; spectral MIS
  // needs glossyLobePdfForLane.
  s.dispersive = dispersive;
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
