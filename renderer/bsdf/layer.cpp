// The coat of a layered BSDF: reflection of the interface and the transmittance factor of the
// base lobes (model and its energy bookkeeping: layer.h, docs/layering.md).
#include <array>
#include <cmath>

#include "renderer/bsdf/bsdf_constants.h"
#include "renderer/bsdf/layer.h"
#include "renderer/bsdf/microfacet.h"

namespace tex::render {
namespace {

constexpr int kAverageQuadrature = 1024;
constexpr int kAverageTableSize = 513;
constexpr float kLogEtaMax = 1.3862944f;  // ln 4

double fresnelAverageDirect(float eta) {
  // Midpoint rule in mu^2 (= cos-weighted measure): 2 mu dmu = d(mu^2).
  double sum = 0;
  for (int k = 0; k < kAverageQuadrature; ++k) {
    const double mu2 = (k + 0.5) / kAverageQuadrature;
    sum += fresnelDielectric(float(std::sqrt(mu2)), eta);
  }
  return sum / kAverageQuadrature;
}

const std::array<float, kAverageTableSize>& fresnelAverageTable() {
  static const std::array<float, kAverageTableSize> table = [] {
    std::array<float, kAverageTableSize> t{};
    for (int i = 0; i < kAverageTableSize; ++i) {
      const float logEta = -kLogEtaMax + 2.0f * kLogEtaMax * float(i) / float(kAverageTableSize - 1);
      t[size_t(i)] = float(fresnelAverageDirect(std::exp(logEta)));
    }
    return t;
  }();
  return table;
}

bool usableEta(float eta) { return eta > 0.0f && std::isfinite(eta) && eta != 1.0f; }

float laneEta(const Lobe& coat, int lane) { return coat.etaVaries ? coat.a.v[lane] : coat.a.v[0]; }

}  // namespace

float fresnelDielectricAverage(float eta) {
  if (eta == 1.0f) return 0.0f;
  if (!(eta > 0.0f) || !std::isfinite(eta)) return 1.0f;
  const float logEta = std::log(eta);
  if (std::fabs(logEta) > kLogEtaMax) return float(fresnelAverageDirect(eta));
  const float x = (logEta + kLogEtaMax) / (2.0f * kLogEtaMax) * float(kAverageTableSize - 1);
  const int i = std::min(int(x), kAverageTableSize - 2);
  const float t = x - float(i);
  const auto& table = fresnelAverageTable();
  return table[size_t(i)] * (1.0f - t) + table[size_t(i + 1)] * t;
}

bool coatIsSpecular(const Lobe& coat) { return coat.kind != LobeKind::RoughDielectric; }

float coatSelectionReflectance(const Lobe& coat, const Vec3& wo) {
  const float eta = coat.a.v[0];
  return usableEta(eta) ? fresnelDielectric(std::fabs(wo.z), eta) : 0.0f;
}

Spectrum coatTransmittance(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  Spectrum t;
  const float cosO = std::fabs(wo.z), cosI = std::fabs(wi.z);
  for (int i = 0; i < kLanes; ++i) {
    const float eta = laneEta(coat, i);
    if (!usableEta(eta)) {
      t.v[i] = 1.0f;
      continue;
    }
    const float oneMinusAverage = 1.0f - fresnelDielectricAverage(eta);
    t.v[i] = oneMinusAverage > 0.0f ? (1.0f - fresnelDielectric(cosO, eta)) * (1.0f - fresnelDielectric(cosI, eta)) /
                                          oneMinusAverage
                                    : 0.0f;
  }
  return t;
}

Spectrum coatEval(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  if (coatIsSpecular(coat)) return Spectrum();
  Lobe reflection = coat;
  if (!coat.etaVaries)
    for (int i = 1; i < kLanes; ++i) reflection.a.v[i] = coat.a.v[0];
  return ggxDielectricReflectionEval(reflection, wo, wi);
}

float coatPdf(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  return coatIsSpecular(coat) ? 0.0f : ggxDielectricReflectionPdf(coat, wo, wi);
}

std::optional<BsdfSample> coatSample(const Lobe& coat, const Vec3& wo, Vec2 u2) {
  if (!coatIsSpecular(coat)) {
    std::optional<BsdfSample> s = ggxDielectricReflectionSample(coat, wo, u2);
    if (s) s->f = coatEval(coat, wo, s->wi);
    return s;
  }
  const float cosO = std::fabs(wo.z);
  if (!(cosO >= kMinCosTheta)) return std::nullopt;
  BsdfSample s;
  s.specular = true;
  s.wi = Vec3(-wo.x, -wo.y, wo.z);
  s.pdfW = 1.0f;  // the mirror is the coat's only event; Bsdf multiplies its selection probability
  for (int i = 0; i < kLanes; ++i) {
    const float eta = laneEta(coat, i);
    if (coat.weight.v[i] != 0.0f && usableEta(eta)) s.f.v[i] = coat.weight.v[i] * fresnelDielectric(cosO, eta) / cosO;
  }
  return s;
}

}  // namespace tex::render
