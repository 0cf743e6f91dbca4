// The factors of layers over a whole Bsdf (model: covers.h).
#include "renderer/bsdf/covers.h"

#include <algorithm>
#include <cmath>

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

// Midpoint rule in mu^2 (2 mu dmu = d(mu^2)), computed when a Bsdf gets its second coat: 128
// nodes keep a white base under two coats within ~1e-4 of albedo 1 (test
// GltfExtensions.ClearcoatOverWhitePlasticIsLossless).
constexpr int kAverageNodes = 128;

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
  Spectrum t;
  for (int i = 0; i < kLanes; ++i)
    t.v[i] = 1.0f - clampedCoverage(coverage, i) * std::max(laneFresnel(coat, i, cosO), laneFresnel(coat, i, cosI));
  return t;
}

Spectrum twoCoatAverageTransmission(const Lobe& outer, const Lobe& inner, const Spectrum& innerCoverage) {
  Spectrum average;
  for (int lane = 0; lane < kLanes; ++lane) {
    const float etaOut = laneEta(outer, lane), etaIn = laneEta(inner, lane), k = clampedCoverage(innerCoverage, lane);
    // Lanes with lane 0's parameters (all of them for most materials) share its integral.
    if (lane > 0 && etaOut == laneEta(outer, 0) && etaIn == laneEta(inner, 0) && k == clampedCoverage(innerCoverage, 0)) {
      average.v[lane] = average.v[0];
      continue;
    }
    double sum = 0.0;
    for (int n = 0; n < kAverageNodes; ++n) {
      const float mu = float(std::sqrt((n + 0.5) / kAverageNodes));
      sum += double(1.0f - laneFresnel(outer, lane, mu)) * double(1.0f - k * laneFresnel(inner, lane, mu));
    }
    average.v[lane] = float(sum / kAverageNodes);
  }
  return average;
}

Spectrum twoCoatTransmittance(const Lobe& outer, const Spectrum& outerCoverage, const Lobe& inner,
                              const Spectrum& innerCoverage, const Spectrum& average, float outerCosO,
                              float outerCosI, float cosO, float cosI) {
  const Spectrum innerAlone = coveredTransmittance(inner, innerCoverage, cosO, cosI);
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) {
    const float kIn = clampedCoverage(innerCoverage, i), kOut = clampedCoverage(outerCoverage, i);
    const float through = (1.0f - laneFresnel(outer, i, outerCosO)) * (1.0f - kIn * laneFresnel(inner, i, cosO)) *
                          (1.0f - laneFresnel(outer, i, outerCosI)) * (1.0f - kIn * laneFresnel(inner, i, cosI));
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
