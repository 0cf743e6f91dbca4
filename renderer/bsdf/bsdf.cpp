// The lobe mixture at one shading point: world <-> shading frame, lobe selection, the
// geometric-normal leak test and the adjoint shading-normal correction (Veach 1997, 5.3).
#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/bsdf_constants.h"

namespace tex::render {
namespace {

// The cosines of one direction pair with the shading normal (local z) and the geometric one.
struct PairCosines {
  float woNs, wiNs, woNg, wiNg;
};

bool degenerate(float cosTheta) { return !(std::fabs(cosTheta) >= kMinCosTheta); }  // also NaN

// Light leaks: a direction counts only when the shading and the geometric normal agree on
// whether the pair is a reflection (same side) or a transmission (opposite sides).
bool sidesAgree(const PairCosines& c) {
  if (degenerate(c.wiNs) || degenerate(c.wiNg)) return false;
  return (c.woNs * c.wiNs > 0.0f) == (c.woNg * c.wiNg > 0.0f);
}

// Importance transport with shading normals is not reciprocal: the adjoint BSDF carries
// |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997, eq. 5.19). All cosines are non-degenerate here.
float shadingNormalCorrection(const PairCosines& c, TransportMode mode) {
  if (mode == TransportMode::Radiance) return 1.0f;
  return std::fabs(c.woNs * c.wiNg) / std::fabs(c.woNg * c.wiNs);
}

}  // namespace

bool Bsdf::add(const Lobe& lobe) {
  if (count_ >= kMaxLobes) return false;
  lobes_[count_++] = lobe;
  return true;
}

// Sum of |weight| over all 8 lanes. Lanes past the group's count are zero (spectrum.h), so this
// is count * (mean over the group): proportional to the mean, without needing the count.
float Bsdf::selectionWeight(int i) const {
  float sum = 0.0f;
  for (int lane = 0; lane < kLanes; ++lane) sum += std::fabs(lobes_[i].weight.v[lane]);
  return std::isfinite(sum) ? sum : 0.0f;
}

bool Bsdf::hasNonSpecular() const {
  for (int i = 0; i < count_; ++i)
    if (!lobeIsSpecular(lobes_[i].kind) && selectionWeight(i) > 0.0f) return true;
  return false;
}

Spectrum Bsdf::eval(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) return Spectrum();
  Spectrum f;
  for (int i = 0; i < count_; ++i)
    if (!lobeIsSpecular(lobes_[i].kind)) f += lobeEval(lobes_[i], wo, wi, mode);
  return f * shadingNormalCorrection(c, mode);
}

float Bsdf::pdf(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  // Rejected directions have density 0, matching sample(), which drops them.
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) return 0.0f;
  float total = 0.0f, pdfW = 0.0f;
  for (int i = 0; i < count_; ++i) {
    const float w = selectionWeight(i);
    total += w;
    if (w > 0.0f && !lobeIsSpecular(lobes_[i].kind)) pdfW += w * lobePdf(lobes_[i], wo, wi, mode);
  }
  return total > 0.0f ? pdfW / total : 0.0f;
}

float Bsdf::pdfForLane(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode, int lane) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) return 0.0f;
  float total = 0.0f, pdfW = 0.0f;
  for (int i = 0; i < count_; ++i) {
    const float w = selectionWeight(i);
    total += w;
    if (w > 0.0f && !lobeIsSpecular(lobes_[i].kind)) pdfW += w * lobePdfForLane(lobes_[i], wo, wi, mode, lane);
  }
  return total > 0.0f ? pdfW / total : 0.0f;
}

std::optional<BsdfSample> Bsdf::sample(const Vec3& woWorld, float uc, Vec2 u2, TransportMode mode) const {
  const Vec3 wo = frame_.toLocal(woWorld);
  const float woNg = dot3(woWorld, ng_);
  if (degenerate(wo.z) || degenerate(woNg)) return std::nullopt;

  float weights[kMaxLobes];
  float total = 0.0f;
  for (int i = 0; i < count_; ++i) total += weights[i] = selectionWeight(i);
  if (!(total > 0.0f)) return std::nullopt;

  // Pick a lobe with uc and stretch uc's sub-interval back to [0,1) for the lobe's own choice.
  const float target = uc * total;
  float cdfBefore = 0.0f;
  int chosen = -1, lastNonZero = -1;
  for (int i = 0; i < count_; ++i) {
    if (weights[i] <= 0.0f) continue;
    lastNonZero = i;
    if (target < cdfBefore + weights[i]) {
      chosen = i;
      break;
    }
    cdfBefore += weights[i];
  }
  if (chosen < 0) {  // uc * total rounded up past the last interval
    chosen = lastNonZero;
    cdfBefore = total - weights[chosen];
  }
  const float ucLobe = std::clamp((target - cdfBefore) / weights[chosen], 0.0f, kOneMinusEpsilon);
  const float selectionPdf = weights[chosen] / total;

  std::optional<BsdfSample> s = lobeSample(lobes_[chosen], wo, ucLobe, u2, mode);
  if (!s) return std::nullopt;
  const Vec3 wi = s->wi;
  const Vec3 wiWorld = frame_.toWorld(wi);
  const PairCosines c{wo.z, wi.z, woNg, dot3(wiWorld, ng_)};
  if (!sidesAgree(c)) return std::nullopt;

  if (s->specular) {
    s->pdfW *= selectionPdf;  // the Dirac lobe's own f; the others have no mass on its direction
  } else {
    // The direction could have come from any non-specular lobe: the mixture's f and pdf.
    Spectrum f;
    float pdfW = 0.0f;
    for (int i = 0; i < count_; ++i) {
      if (weights[i] <= 0.0f || lobeIsSpecular(lobes_[i].kind)) continue;
      f += lobeEval(lobes_[i], wo, wi, mode);
      pdfW += weights[i] * lobePdf(lobes_[i], wo, wi, mode);
    }
    pdfW /= total;
    if (!(pdfW > 0.0f)) return std::nullopt;
    s->f = f;
    s->pdfW = pdfW;
  }
  s->f *= shadingNormalCorrection(c, mode);
  s->wi = wiWorld;
  return s;
}

}  // namespace tex::render
