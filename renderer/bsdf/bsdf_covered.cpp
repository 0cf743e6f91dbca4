// The Bsdf's evaluation and sampling with covers (covers.h: a partial coat, a clearcoat, a sheen
// cover). Kept apart from bsdf.cpp's paths, which Bsdfs without covers take unchanged.
#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf.h"
#include "renderer/bsdf/covers.h"
#include "renderer/bsdf/lambertian.h"
#include "renderer/bsdf/layer.h"

namespace tex::render {

Spectrum Bsdf::localEvalCovered(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  const Covers& c = covers_.c;
  const float cosO = std::fabs(wo.z), cosI = std::fabs(wi.z);
  // Lobes by what covers them: spread (Lambertian) or directional, under the coat or not; the
  // sheen cover's own lobes (Sheen lobes not under the coat) are under the clearcoat only.
  Spectrum spread, spreadCoated, directional, directionalCoated, sheens;
  for (int i = 0; i < count_; ++i) {
    const Lobe& lobe = storage_.lobes[i];
    if (lobeIsSpecular(lobe.kind)) continue;
    const Spectrum fLobe = lobe.kind == LobeKind::Lambertian ? lambertianEval(lobe, wo, wi) : lobeEval(lobe, wo, wi, mode);
    const bool coated = hasCoat_ && lobe.underCoat;
    if (c.hasSheenCover && !coated && lobe.kind == LobeKind::Sheen) sheens += fLobe;
    else if (spreadsOverTheHemisphere(lobe.kind)) (coated ? spreadCoated : spread) += fLobe;
    else (coated ? directionalCoated : directional) += fLobe;
  }
  if (hasCoat_) {
    if (!directionalCoated.isBlack())
      directional += directionalCoated * coveredTransmittanceDirectional(coat_, c.coatCoverage, cosO, cosI);
    directional += coatEval(coat_, wo, wi);  // its weight carries its coverage
    // Under a clearcoat too, the two interfaces' transmittance is taken together (below).
    if (!c.hasClearcoat && !spreadCoated.isBlack()) {
      spread += spreadCoated * coveredTransmittance(coat_, c.coatCoverage, cosO, cosI);
      spreadCoated = Spectrum();
    }
  } else {
    spread += spreadCoated;
    spreadCoated = Spectrum();
  }
  if (c.hasSheenCover) {
    const Spectrum scale = sheenCoverFactor(c.sheenColour, c.sheenAlpha, cosO, cosI);
    spread *= scale;
    spreadCoated *= scale;
    directional *= scale;
  }
  directional += sheens;
  if (!c.hasClearcoat) return spread + directional;
  const Vec3 woCoat = toClearcoat(wo), wiCoat = toClearcoat(wi);
  const float coatO = std::fabs(woCoat.z), coatI = std::fabs(wiCoat.z);
  // The clearcoat reflects only: with its own normal map its frame may see wi above it where
  // the surface's sees it below (a reflection into the surface: a leak on open geometry).
  Spectrum f = wo.z * wi.z > 0.0f ? coatEval(c.clearcoat, woCoat, wiCoat) : Spectrum();
  if (!spread.isBlack()) f += spread * coveredTransmittance(c.clearcoat, c.clearcoatCoverage, coatO, coatI);
  if (!directional.isBlack())
    f += directional * coveredTransmittanceDirectional(c.clearcoat, c.clearcoatCoverage, coatO, coatI);
  if (!spreadCoated.isBlack())
    f += spreadCoated * twoCoatTransmittance(c.clearcoat, c.clearcoatCoverage, coat_, c.coatCoverage,
                                             c.twoCoatAverage, coatO, coatI, cosO, cosI);
  return f;
}

float Bsdf::componentWeightsCovered(const Vec3& wo, float* weights) const {
  const Covers& c = covers_.c;
  // The hero lane's reflected share at wo goes to each interface, the rest to what it covers.
  const float coatShare =
      hasCoat_ ? std::clamp(c.coatCoverage.v[0], 0.0f, 1.0f) * coatSelectionReflectance(coat_, wo) : 0.0f;
  const float clearcoatShare =
      c.hasClearcoat
          ? std::clamp(c.clearcoatCoverage.v[0], 0.0f, 1.0f) * coatSelectionReflectance(c.clearcoat, toClearcoat(wo))
          : 0.0f;
  float total = 0.0f;
  for (int i = 0; i < count_; ++i) {
    weights[i] = selection_[i] * (1.0f - clearcoatShare);
    if (hasCoat_ && storage_.lobes[i].underCoat) weights[i] *= 1.0f - coatShare;
    total += weights[i];
  }
  weights[count_] = hasCoat_ ? coatSelection_ * coatSelectionReflectance(coat_, wo) * (1.0f - clearcoatShare) : 0.0f;
  weights[count_ + 1] =
      c.hasClearcoat ? c.clearcoatSelection * coatSelectionReflectance(c.clearcoat, toClearcoat(wo)) : 0.0f;
  return total + weights[count_] + weights[count_ + 1];
}

Spectrum Bsdf::coverFactorOfSpecular(int chosen, const Vec3& wo, const Vec3& wi) const {
  const Covers& c = covers_.c;
  const float cosO = std::fabs(wo.z), cosI = std::fabs(wi.z);
  Spectrum factor(1.0f);
  const bool isCoat = chosen == count_;
  const Lobe* lobe = isCoat ? nullptr : &storage_.lobes[chosen];
  if (lobe && hasCoat_ && lobe->underCoat) factor *= coveredTransmittanceDirectional(coat_, c.coatCoverage, cosO, cosI);
  const bool sheenItself = lobe && lobe->kind == LobeKind::Sheen && !(hasCoat_ && lobe->underCoat);
  if (c.hasSheenCover && !sheenItself) factor *= sheenCoverFactor(c.sheenColour, c.sheenAlpha, cosO, cosI);
  if (c.hasClearcoat)
    factor *= coveredTransmittanceDirectional(c.clearcoat, c.clearcoatCoverage, std::fabs(toClearcoat(wo).z),
                                              std::fabs(toClearcoat(wi).z));
  return factor;
}

Spectrum Bsdf::clearcoatEmissionFactor(const Vec3& woWorld) const {
  if (!hasClearcoat()) return Spectrum(1.0f);
  const float cosCoat = std::fabs(toClearcoat(frame_.toLocal(woWorld)).z);
  return coveredTransmittanceDirectional(covers_.c.clearcoat, covers_.c.clearcoatCoverage, cosCoat, cosCoat);
}

std::optional<BsdfSample> Bsdf::clearcoatSample(const Vec3& wo, Vec2 u2) const {
  const Vec3 woCoat = toClearcoat(wo);
  std::optional<BsdfSample> s = coatSample(covers_.c.clearcoat, woCoat, u2);
  if (!s) return s;
  s->wi = fromClearcoat(s->wi);
  if (!(s->wi.z * wo.z > 0.0f)) return std::nullopt;  // reflected into the surface (localEvalCovered)
  // A mirror in its own frame: F / |cos| with the cosine the integrator multiplies by, the
  // Bsdf's (the sample's f had the clearcoat's).
  if (s->specular) {
    const float cosBase = std::fabs(s->wi.z);
    if (!(cosBase > 0.0f)) return std::nullopt;
    s->f *= std::fabs(woCoat.z) / cosBase;
  }
  return s;
}

}  // namespace tex::render
