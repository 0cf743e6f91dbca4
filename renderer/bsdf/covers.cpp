// The factors of layers over a whole Bsdf (model: covers.h).
#include "renderer/bsdf/covers.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/bsdf/layer.h"
#include "renderer/bsdf/sheen_albedo.h"

namespace tex::render {
namespace {

bool usableEta(float eta) { return eta > 0.0f && std::isfinite(eta) && eta != 1.0f; }
float laneEta(const Lobe& coat, int lane) { return coat.etaVaries ? coat.a.v[lane] : coat.a.v[0]; }
float laneFresnel(const Lobe& coat, int lane, float cosTheta) {
  const float eta = laneEta(coat, lane);
  return usableEta(eta) ? fresnelDielectric(cosTheta, eta) : 0.0f;
}
float clampedCoverage(const Spectrum& k, int lane) { return std::clamp(k.v[lane], 0.0f, 1.0f); }  // NaN -> 0

// The overlap C(eta_o, eta_i) = 2 int_0^1 (1 - F_o(mu)) F_i(mu) mu dmu, so that the two-coat
// average is 1 - F_avg(eta_o) - k C: by the midpoint rule in mu^2 (2 mu dmu = d(mu^2)), and
// tabulated over ln eta in [-ln 4, ln 4]^2 (bilinear): computed per hit it had made a textured
// clearcoat 4 times slower to shade. 1024 nodes as fresnelDielectricAverage uses, so the two
// averages agree and a white base under two coats stays at albedo 1 to ~1e-4 (test
// GltfExtensions.ClearcoatAndSpecularOverWhitePlasticAreLossless).
constexpr int kOverlapNodes = 1024;
constexpr int kOverlapTableSize = 65;
constexpr float kLogEtaMax = 1.3862944f;  // ln 4

double overlapDirect(float etaO, float etaI) {
  double sum = 0.0;
  for (int n = 0; n < kOverlapNodes; ++n) {
    const float mu = float(std::sqrt((n + 0.5) / kOverlapNodes));
    sum += double(1.0f - fresnelDielectric(mu, etaO)) * double(fresnelDielectric(mu, etaI));
  }
  return sum / kOverlapNodes;
}

const std::vector<float>& overlapTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(size_t(kOverlapTableSize * kOverlapTableSize));
    const auto eta = [](int i) {
      return std::exp(-kLogEtaMax + 2.0f * kLogEtaMax * float(i) / float(kOverlapTableSize - 1));
    };
    for (int o = 0; o < kOverlapTableSize; ++o)
      for (int i = 0; i < kOverlapTableSize; ++i) t[size_t(o * kOverlapTableSize + i)] = float(overlapDirect(eta(o), eta(i)));
    return t;
  }();
  return table;
}

// C for two usable IORs (table inside its range, quadrature outside).
float overlap(float etaO, float etaI) {
  const float x = (std::log(etaO) + kLogEtaMax) / (2.0f * kLogEtaMax) * float(kOverlapTableSize - 1);
  const float y = (std::log(etaI) + kLogEtaMax) / (2.0f * kLogEtaMax) * float(kOverlapTableSize - 1);
  if (!(x >= 0.0f && y >= 0.0f && x <= float(kOverlapTableSize - 1) && y <= float(kOverlapTableSize - 1)))
    return float(overlapDirect(etaO, etaI));
  const int xi = std::min(int(x), kOverlapTableSize - 2), yi = std::min(int(y), kOverlapTableSize - 2);
  const float tx = x - float(xi), ty = y - float(yi);
  const std::vector<float>& t = overlapTable();
  const auto at = [&](int o, int i) { return t[size_t(o * kOverlapTableSize + i)]; };
  return (at(xi, yi) * (1.0f - ty) + at(xi, yi + 1) * ty) * (1.0f - tx) +
         (at(xi + 1, yi) * (1.0f - ty) + at(xi + 1, yi + 1) * ty) * tx;
}

}  // namespace

Spectrum coveredTransmittance(const Lobe& coat, const Spectrum& coverage, float cosO, float cosI) {
  const Spectrum full = coatTransmittance(coat, Vec3(0.0f, 0.0f, cosO), Vec3(0.0f, 0.0f, cosI));
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) {
    const float k = clampedCoverage(coverage, i);
    t.v[i] = (1.0f - k) + k * full.v[i];
  }
  return t;
}

Spectrum coveredTransmittanceDirectional(const Lobe& coat, const Spectrum& coverage, float cosO, float cosI) {
  // One IOR for the group (most coats): two Fresnel terms, not two per lane.
  const float shared = coat.etaVaries ? 0.0f : std::max(laneFresnel(coat, 0, cosO), laneFresnel(coat, 0, cosI));
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) {
    const float f = coat.etaVaries ? std::max(laneFresnel(coat, i, cosO), laneFresnel(coat, i, cosI)) : shared;
    t.v[i] = 1.0f - clampedCoverage(coverage, i) * f;
  }
  return t;
}

Spectrum twoCoatAverageTransmission(const Lobe& outer, const Lobe& inner, const Spectrum& innerCoverage) {
  Spectrum average;
  for (int lane = 0; lane < kLanes; ++lane) {
    const float etaOut = laneEta(outer, lane), etaIn = laneEta(inner, lane), k = clampedCoverage(innerCoverage, lane);
    // Lanes with lane 0's parameters (all of them for most materials) share its value.
    if (lane > 0 && etaOut == laneEta(outer, 0) && etaIn == laneEta(inner, 0) && k == clampedCoverage(innerCoverage, 0)) {
      average.v[lane] = average.v[0];
      continue;
    }
    // 1 - F_avg(outer) - k C; an unusable IOR reflects nothing (laneFresnel's 0).
    const bool outerReflects = usableEta(etaOut), innerReflects = usableEta(etaIn);
    const float outerAverage = outerReflects ? fresnelDielectricAverage(etaOut) : 0.0f;
    const float c = !innerReflects ? 0.0f : outerReflects ? overlap(etaOut, etaIn) : fresnelDielectricAverage(etaIn);
    average.v[lane] = 1.0f - outerAverage - k * c;
  }
  return average;
}

Spectrum twoCoatTransmittance(const Lobe& outer, const Spectrum& outerCoverage, const Lobe& inner,
                              const Spectrum& innerCoverage, const Spectrum& average, float outerCosO,
                              float outerCosI, float cosO, float cosI) {
  const Spectrum innerAlone = coveredTransmittance(inner, innerCoverage, cosO, cosI);
  // Each interface's Fresnel terms once when its IOR is one for the group.
  const auto outerThrough = [&](int lane) {
    return (1.0f - laneFresnel(outer, lane, outerCosO)) * (1.0f - laneFresnel(outer, lane, outerCosI));
  };
  const float outerShared = outer.etaVaries ? 0.0f : outerThrough(0);
  const float innerO = inner.etaVaries ? 0.0f : laneFresnel(inner, 0, cosO);
  const float innerI = inner.etaVaries ? 0.0f : laneFresnel(inner, 0, cosI);
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) {
    const float kIn = clampedCoverage(innerCoverage, i), kOut = clampedCoverage(outerCoverage, i);
    const float fO = inner.etaVaries ? laneFresnel(inner, i, cosO) : innerO;
    const float fI = inner.etaVaries ? laneFresnel(inner, i, cosI) : innerI;
    const float through = (outer.etaVaries ? outerThrough(i) : outerShared) * (1.0f - kIn * fO) * (1.0f - kIn * fI);
    const float both = average.v[i] > 0.0f ? through / average.v[i] : 0.0f;
    t.v[i] = (1.0f - kOut) * innerAlone.v[i] + kOut * both;
  }
  return t;
}

Spectrum sheenCoverFactor(const Spectrum& colour, float alpha, float cosO, float cosI) {
  const double a = sheen::clampRoughness(alpha);
  const float e = float(std::max(sheen::boundedAlbedo(a, cosO), sheen::boundedAlbedo(a, cosI)));
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) t.v[i] = 1.0f - std::clamp(colour.v[i], 0.0f, 1.0f) * e;
  return t;
}

}  // namespace tex::render
