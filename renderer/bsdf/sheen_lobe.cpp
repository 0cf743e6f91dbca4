// The sheen lobes: values from sheen_albedo.h's formulas and table, cosine-weighted sampling.
#include "renderer/bsdf/sheen_lobe.h"

#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/sheen_albedo.h"
#include "renderer/core/warp.h"

namespace tex::render {
namespace {

bool degenerate(const Vec3& w) { return !(std::fabs(w.z) >= kMinCosTheta); }  // also NaN

// sheen::boundedAverageAlbedo sums the table's 95 cells (about 200 exp calls): remembered per
// thread for the last few roughnesses, since a path vertex evaluates the same lobe several
// times (NEE, BSDF sample, MIS) and a scene's paths alternate between a few sheen materials
// (one remembered value thrashed between them: exp was 9 % of velvet.json).
double averageBoundedAlbedo(double alpha) {
  constexpr int kEntries = 8;
  struct Entry {
    double alpha = -1.0, average = 0.0;
  };
  thread_local Entry entries[kEntries];
  thread_local int next = 0;
  for (const Entry& e : entries)
    if (e.alpha == alpha) return e.average;
  Entry& e = entries[next];
  next = (next + 1) % kEntries;
  e.average = sheen::boundedAverageAlbedo(alpha);
  e.alpha = alpha;
  return e.average;
}

Spectrum sheenValue(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  const double alpha = sheen::clampRoughness(lobe.roughness);
  const double norm = std::max({1.0, sheen::tabulatedAlbedo(alpha, std::fabs(wo.z)),
                                sheen::tabulatedAlbedo(alpha, std::fabs(wi.z))});
  return lobe.weight * float(sheen::charlieValue(alpha, wo, wi) / norm);
}

Spectrum baseValue(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  const double alpha = sheen::clampRoughness(lobe.roughness);
  const double eo = sheen::boundedAlbedo(alpha, std::fabs(wo.z)), ei = sheen::boundedAlbedo(alpha, std::fabs(wi.z));
  const double average = averageBoundedAlbedo(alpha);
  Spectrum f;
  for (int lane = 0; lane < kLanes; ++lane) {
    const double a = std::clamp(double(lobe.a.v[lane]), 0.0, 1.0);  // NaN -> 0
    const double denominator = 1.0 - a * average;
    // Eb < 1 somewhere on any row, so the denominator stays positive; guard rounding only.
    const double scale = denominator > 1e-9 ? (1.0 - a * eo) * (1.0 - a * ei) / denominator : 0.0;
    f.v[lane] = lobe.weight.v[lane] * float(scale * (1.0 / 3.14159265358979323846));
  }
  return f;
}

}  // namespace

Spectrum sheenLobeEval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
  if (degenerate(wo) || degenerate(wi) || !sameHemisphere(wo, wi)) return Spectrum();
  return lobe.kind == LobeKind::Sheen ? sheenValue(lobe, wo, wi) : baseValue(lobe, wo, wi);
}

float sheenLobePdf(const Vec3& wo, const Vec3& wi) {
  if (degenerate(wo) || degenerate(wi) || !sameHemisphere(wo, wi)) return 0.0f;
  return absCosTheta(wi) * kInvPi;
}

std::optional<BsdfSample> sheenLobeSample(const Lobe& lobe, const Vec3& wo, Vec2 u2) {
  if (degenerate(wo)) return std::nullopt;
  Vec3 wi = sampleCosineHemisphere(u2);
  if (wo.z < 0.0f) wi.z = -wi.z;  // reflection stays on wo's side (two-sided)
  if (degenerate(wi)) return std::nullopt;  // zero density: the pdf says 0 there too
  BsdfSample s;
  s.wi = wi;
  s.f = sheenLobeEval(lobe, wo, wi);
  s.pdfW = absCosTheta(wi) * kInvPi;
  return s;
}

}  // namespace tex::render
