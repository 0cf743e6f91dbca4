// The lobe mixture at one shading point: world <-> shading frame, lobe selection, the
// geometric-normal leak test, the adjoint shading-normal correction (Veach 1997, 5.3) and the
// coat of a layer (layer.h).
#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/covers.h"
#include "renderer/bsdf/lambertian.h"
#include "renderer/bsdf/layer.h"
#include "renderer/bsdf/microfacet.h"

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
  selection_[count_] = selectionWeight(lobe);
  const bool nonSpecular = !lobeIsSpecular(lobe.kind);
  hasNonSpecular_ = hasNonSpecular_ || (nonSpecular && selection_[count_] > 0.0f);
  // A rough thin wall's lanes differ in R' only, not in their density (thin_dielectric.cpp).
  hasDispersiveDensity_ =
      hasDispersiveDensity_ || (nonSpecular && lobe.etaVaries && lobe.kind != LobeKind::RoughThinDielectric);
  storage_.lobes[count_++] = lobe;
  return true;
}

bool Bsdf::setCoat(const Lobe& coat) {
  if (hasCoat_ || (coat.kind != LobeKind::SmoothDielectric && coat.kind != LobeKind::RoughDielectric)) return false;
  coat_ = coat;
  hasCoat_ = true;
  coatSelection_ = selectionWeight(coat);
  hasNonSpecular_ = hasNonSpecular_ || (!coatIsSpecular(coat_) && coatSelection_ > 0.0f);
  if (covered_) updateTwoCoatAverage();
  return true;
}

void Bsdf::startCovers() {
  if (covered_) return;
  covered_ = true;
  Covers& c = covers_.c;
  c = Covers{};
  c.coatCoverage = Spectrum(1.0f);
  c.hasClearcoat = false;
  c.clearcoatCoverage = Spectrum(1.0f);
  c.clearcoatSelection = 0.0f;
  c.clearcoatOwnFrame = false;
  c.hasSheenCover = false;
  c.sheenAlpha = 0.0f;
}

void Bsdf::updateTwoCoatAverage() {
  Covers& c = covers_.c;
  if (hasCoat_ && c.hasClearcoat) c.twoCoatAverage = twoCoatAverageTransmission(c.clearcoat, coat_, c.coatCoverage);
}

bool Bsdf::setPartialCoat(const Lobe& coat, const Spectrum& coverage) {
  if (hasCoat_) return false;
  startCovers();
  covers_.c.coatCoverage = coverage;
  return setCoat(coat);  // with the coverage in place for the two-coat average
}

bool Bsdf::setClearcoat(const Lobe& interface, const Spectrum& coverage) {
  if (hasClearcoat() || (interface.kind != LobeKind::SmoothDielectric && interface.kind != LobeKind::RoughDielectric))
    return false;
  startCovers();
  Covers& c = covers_.c;
  c.hasClearcoat = true;
  c.clearcoat = interface;
  c.clearcoatCoverage = coverage;
  c.clearcoatSelection = selectionWeight(interface);
  hasNonSpecular_ = hasNonSpecular_ || (!coatIsSpecular(interface) && c.clearcoatSelection > 0.0f);
  updateTwoCoatAverage();
  return true;
}

void Bsdf::setClearcoatFrame(const Frame& worldFrame) {
  startCovers();
  covers_.c.clearcoatFrame = Frame::fromNormalTangent(frame_.toLocal(worldFrame.n), frame_.toLocal(worldFrame.s));
  covers_.c.clearcoatOwnFrame = true;
}

bool Bsdf::setSheenCover(const Spectrum& colour, float alpha) {
  if (hasSheenCover()) return false;
  startCovers();
  covers_.c.hasSheenCover = true;
  covers_.c.sheenColour = colour;
  covers_.c.sheenAlpha = alpha;
  return true;
}

Vec3 Bsdf::toClearcoat(const Vec3& local) const {
  return covers_.c.clearcoatOwnFrame ? covers_.c.clearcoatFrame.toLocal(local) : local;
}
Vec3 Bsdf::fromClearcoat(const Vec3& clearcoatLocal) const {
  return covers_.c.clearcoatOwnFrame ? covers_.c.clearcoatFrame.toWorld(clearcoatLocal) : clearcoatLocal;
}

void Bsdf::copyLobesFrom(const Bsdf& other) {
  count_ = other.count_;
  for (int i = 0; i < count_; ++i) {
    storage_.lobes[i] = other.storage_.lobes[i];
    selection_[i] = other.selection_[i];
  }
  hasCoat_ = other.hasCoat_;
  if (hasCoat_) coat_ = other.coat_;
  coatSelection_ = other.coatSelection_;
  hasNonSpecular_ = other.hasNonSpecular_;
  hasDispersiveDensity_ = other.hasDispersiveDensity_;
  covered_ = other.covered_;
  if (covered_) covers_.c = other.covers_.c;
}

// Sum of |weight| over all 8 lanes. Lanes past the group's count are zero (spectrum.h), so this
// is count * (mean over the group): proportional to the mean, without needing the count.
// A group of 4 wavelengths leaves lanes 4-7 zero, and adding |0| = +0 to the sum (never -0)
// changes no bit: then the chain of dependent additions stops at lane 4.
float Bsdf::selectionWeight(const Lobe& l) {
  static_assert(kLanes == 8);
  float sum = 0.0f;
  for (int lane = 0; lane < 4; ++lane) sum += std::fabs(l.weight.v[lane]);
  if (!l.weight.upperLanesZero())
    for (int lane = 4; lane < kLanes; ++lane) sum += std::fabs(l.weight.v[lane]);
  return std::isfinite(sum) ? sum : 0.0f;
}

float Bsdf::componentWeights(const Vec3& wo, float* weights) const {
  if (covered_) return componentWeightsCovered(wo, weights);
  // With a coat, the share reflected at wo goes to the coat and the rest to the coated lobes.
  const float coatShare = hasCoat_ ? coatSelectionReflectance(coat_, wo) : 0.0f;
  float total = 0.0f;
  for (int i = 0; i < count_; ++i) {
    weights[i] = selection_[i];
    if (hasCoat_ && storage_.lobes[i].underCoat) weights[i] *= 1.0f - coatShare;
    total += weights[i];
  }
  weights[count_] = hasCoat_ ? coatSelection_ * coatShare : 0.0f;
  return total + weights[count_];
}

Spectrum Bsdf::localEval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  if (covered_) return localEvalCovered(wo, wi, mode);
  // Base lobes under a coat, by the transmittance they take (layer.h): spread over the
  // hemisphere (Lambertian) or near the mirror direction (glossy, conductors, sheen).
  Spectrum f, coated, coatedDirectional;
  for (int i = 0; i < count_; ++i) {
    if (lobeIsSpecular(storage_.lobes[i].kind)) continue;
    const Lobe& lobe = storage_.lobes[i];
    const Spectrum fLobe = lobe.kind == LobeKind::Lambertian ? lambertianEval(lobe, wo, wi) : lobeEval(lobe, wo, wi, mode);
    if (hasCoat_ && lobe.underCoat) {
      (spreadsOverTheHemisphere(lobe.kind) ? coated : coatedDirectional) += fLobe;
    } else {
      f += fLobe;
    }
  }
  if (hasCoat_) {
    if (!coated.isBlack()) f += coated * coatTransmittance(coat_, wo, wi);
    if (!coatedDirectional.isBlack()) f += coatedDirectional * coatTransmittanceDirectional(coat_, wo, wi);
    f += coatEval(coat_, wo, wi);
  }
  return f;
}

float Bsdf::localPdf(const Vec3& wo, const Vec3& wi, TransportMode mode, int lane) const {
  float weights[kMaxLobes + 2];
  const float total = componentWeights(wo, weights);
  return localPdf(wo, wi, mode, lane, weights, total);
}

float Bsdf::localPdf(const Vec3& wo, const Vec3& wi, TransportMode mode, int lane, const float* weights, float total) const {
  if (!(total > 0.0f)) return 0.0f;
  float pdfW = 0.0f;
  for (int i = 0; i < count_; ++i) {
    const Lobe& lobe = storage_.lobes[i];
    if (weights[i] > 0.0f && !lobeIsSpecular(lobe.kind))
      pdfW += weights[i] * (lobe.kind == LobeKind::Lambertian ? lambertianPdf(wo, wi)
                            : lane == 0                      ? lobePdf(lobe, wo, wi, mode)
                                                             : lobePdfForLane(lobe, wo, wi, mode, lane));
  }
  if (weights[count_] > 0.0f) pdfW += weights[count_] * coatPdf(coat_, wo, wi);
  if (covered_ && weights[count_ + 1] > 0.0f)
    pdfW += weights[count_ + 1] * coatPdf(covers_.c.clearcoat, toClearcoat(wo), toClearcoat(wi));
  return pdfW / total;
}

namespace {
void immerseLobe(Lobe& lobe, const Spectrum& outside, bool outsideVaries) {
  switch (lobe.kind) {
    case LobeKind::SmoothDielectric:
    case LobeKind::RoughDielectric:
    case LobeKind::GlossyDielectric:
    case LobeKind::ThinDielectric:
    case LobeKind::RoughThinDielectric:
      for (int i = 0; i < kLanes; ++i) lobe.a.v[i] /= outside.v[i];
      lobe.etaVaries = lobe.etaVaries || outsideVaries;
      return;
    case LobeKind::SmoothConductor:
    case LobeKind::RoughConductor:
      for (int i = 0; i < kLanes; ++i) lobe.a.v[i] /= outside.v[i], lobe.b.v[i] /= outside.v[i];
      return;
    default:
      return;
  }
}
}  // namespace

void Bsdf::immerse(const Spectrum& outside, bool outsideVaries) {
  for (int i = 0; i < count_; ++i) {
    Lobe& lobe = storage_.lobes[i];
    immerseLobe(lobe, outside, outsideVaries);
    hasDispersiveDensity_ = hasDispersiveDensity_ ||
                            (!lobeIsSpecular(lobe.kind) && lobe.etaVaries && lobe.kind != LobeKind::RoughThinDielectric);
  }
  if (hasCoat_) immerseLobe(coat_, outside, outsideVaries);
  if (hasClearcoat()) {
    immerseLobe(covers_.c.clearcoat, outside, outsideVaries);
    updateTwoCoatAverage();
  }
}

Spectrum Bsdf::straightThrough(const Vec3& wWorld) const {
  Spectrum t;
  const float cosTheta = dot3(wWorld, frame_.n);
  for (int i = 0; i < count_; ++i) {
    const Lobe& lobe = storage_.lobes[i];
    if (lobe.kind == LobeKind::ThinDielectric && !(hasCoat_ && lobe.underCoat)) t += thinDielectricStraightThrough(lobe, cosTheta);
  }
  if (covered_ && !t.isBlack()) {
    // What passes straight through crosses the covers too (their directional factors).
    const Covers& c = covers_.c;
    const float cosAbs = std::fabs(cosTheta);
    if (c.hasSheenCover) t *= sheenCoverFactor(c.sheenColour, c.sheenAlpha, cosAbs, cosAbs);
    if (c.hasClearcoat) {
      const float cosCoat = std::fabs(toClearcoat(frame_.toLocal(wWorld)).z);
      t *= coveredTransmittanceDirectional(c.clearcoat, c.clearcoatCoverage, cosCoat, cosCoat);
    }
  }
  return t;
}

Spectrum Bsdf::eval(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) return Spectrum();
  return localEval(wo, wi, mode) * shadingNormalCorrection(c, mode);
}

Spectrum Bsdf::evalWithPdf(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode, float& pdfW) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) {
    pdfW = 0.0f;
    return Spectrum();
  }
  pdfW = localPdf(wo, wi, mode, 0);
  return localEval(wo, wi, mode) * shadingNormalCorrection(c, mode);
}

float Bsdf::pdf(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode) const {
  return pdfForLane(woWorld, wiWorld, mode, 0);
}

float Bsdf::pdfForLane(const Vec3& woWorld, const Vec3& wiWorld, TransportMode mode, int lane) const {
  const Vec3 wo = frame_.toLocal(woWorld), wi = frame_.toLocal(wiWorld);
  const PairCosines c{wo.z, wi.z, dot3(woWorld, ng_), dot3(wiWorld, ng_)};
  // Rejected directions have density 0, matching sample(), which drops them.
  if (degenerate(c.woNs) || degenerate(c.woNg) || !sidesAgree(c)) return 0.0f;
  return localPdf(wo, wi, mode, lane);
}

int Bsdf::chooseComponent(const Vec3& wo, float uc, float* weights, float& total, float& ucLobe) const {
  total = componentWeights(wo, weights);
  if (!(total > 0.0f)) return -1;
  // The coat (weight 0 without one) after the lobes, and with covers the clearcoat last.
  const int components = count_ + (covered_ ? 2 : 1);

  // Pick a component with uc and stretch uc's sub-interval back to [0,1) for its own choice.
  const float target = uc * total;
  float cdfBefore = 0.0f;
  int chosen = -1, lastNonZero = -1;
  for (int i = 0; i < components; ++i) {
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
  ucLobe = std::clamp((target - cdfBefore) / weights[chosen], 0.0f, kOneMinusEpsilon);
  return chosen;
}

std::optional<BsdfSample> Bsdf::sample(const Vec3& woWorld, float uc, Vec2 u2, TransportMode mode) const {
  const Vec3 wo = frame_.toLocal(woWorld);
  const float woNg = dot3(woWorld, ng_);
  float weights[kMaxLobes + 2];
  float total = 0.0f, ucLobe = 0.0f;
  const int chosen = degenerate(wo.z) || degenerate(woNg) ? -1 : chooseComponent(wo, uc, weights, total, ucLobe);
  const bool coatChosen = chosen == count_;
  const bool clearcoatChosen = chosen == count_ + 1;
  // Every return names s, so s is the caller's object and the lobe writes its sample there:
  // a local copy returned at the end was read back in 16-byte pieces over the lobe's narrower
  // stores (a store-forwarding stall).
  // The Lambertian lobe inline (lambertian.h), the others through lobeSample's dispatch.
  std::optional<BsdfSample> s = chosen < 0  ? std::optional<BsdfSample>()
                                : coatChosen ? coatSample(coat_, wo, u2)
                                : clearcoatChosen ? clearcoatSample(wo, u2)
                                : storage_.lobes[chosen].kind == LobeKind::Lambertian
                                    ? lambertianSample(storage_.lobes[chosen], wo, u2)
                                    : lobeSample(storage_.lobes[chosen], wo, ucLobe, u2, mode);
  if (!s) return s;
  const Vec3 wi = s->wi;
  const Vec3 wiWorld = frame_.toWorld(wi);
  const PairCosines c{wo.z, wi.z, woNg, dot3(wiWorld, ng_)};
  if (!sidesAgree(c)) {
    s.reset();
    return s;
  }

  if (s->specular) {
    s->pdfW *= weights[chosen] / total;  // the Dirac lobe's own f; the others have no mass on its direction
    // A Dirac base lobe under a coat (a mirror, glass) takes the directional transmittance.
    if (covered_) {
      if (!clearcoatChosen) s->f *= coverFactorOfSpecular(chosen, wo, wi);
    } else if (!coatChosen && hasCoat_ && storage_.lobes[chosen].underCoat) {
      s->f *= coatTransmittanceDirectional(coat_, wo, wi);
    }
    // The lobes straightThrough sums (it leaves out walls under a coat; the covers' factors
    // are in both).
    s->straight = s->transmission && !coatChosen && !clearcoatChosen && storage_.lobes[chosen].kind == LobeKind::ThinDielectric &&
                  !(hasCoat_ && storage_.lobes[chosen].underCoat);
  } else {
    // The direction could have come from any non-specular component: the mixture's f and pdf.
    // For a lone Lambertian lobe, localEval and localPdf would re-evaluate the lobe that made
    // the sample: its own values, summed and weighted as they do (0 + f; (0 + w p) / total).
    if (isLoneLambertian()) {
      s->f = Spectrum() + s->f;
      s->pdfW = (0.0f + weights[0] * s->pdfW) / total;
    } else {
      s->f = localEval(wo, wi, mode);
      s->pdfW = localPdf(wo, wi, mode, 0, weights, total);
    }
    if (!(s->pdfW > 0.0f)) {
      s.reset();
      return s;
    }
    // Every lane's density differs at this vertex when a lobe's does (bsdf.h, `dispersive`).
    s->dispersive = s->dispersive || hasDispersiveDensity_;
  }
  s->f *= shadingNormalCorrection(c, mode);
  s->wi = wiWorld;
  return s;
}

}  // namespace tex::render
