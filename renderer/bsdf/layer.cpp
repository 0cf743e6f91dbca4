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

namespace {

float laneTransmittance(float eta, float cosO, float cosI) {
  if (!usableEta(eta)) return 1.0f;
  const float oneMinusAverage = 1.0f - fresnelDielectricAverage(eta);
  return oneMinusAverage > 0.0f
             ? (1.0f - fresnelDielectric(cosO, eta)) * (1.0f - fresnelDielectric(cosI, eta)) / oneMinusAverage
             : 0.0f;
}

}  // namespace

Spectrum coatTransmittance(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  const float cosO = std::fabs(wo.z), cosI = std::fabs(wi.z);
  // One IOR for the group (a coat's always, closure_lobes.cpp): one value for every lane, not
  // three Fresnel terms and a logarithm per lane.
  if (!coat.etaVaries) return Spectrum(laneTransmittance(coat.a.v[0], cosO, cosI));
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) t.v[i] = laneTransmittance(coat.a.v[i], cosO, cosI);
  return t;
}

Spectrum coatTransmittanceDirectional(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  const float cosO = std::fabs(wo.z), cosI = std::fabs(wi.z);
  const auto lane = [&](float eta) {
    return usableEta(eta) ? 1.0f - std::max(fresnelDielectric(cosO, eta), fresnelDielectric(cosI, eta)) : 1.0f;
  };
  if (!coat.etaVaries) return Spectrum(lane(coat.a.v[0]));
  Spectrum t;
  for (int i = 0; i < kLanes; ++i) t.v[i] = lane(coat.a.v[i]);
  return t;
}

Spectrum coatEval(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  if (coatIsSpecular(coat)) return Spectrum();
  return ggxDielectricReflectionEval(coat, wo, wi);  // lane IORs as laneEta gives them
}

float coatPdf(const Lobe& coat, const Vec3& wo, const Vec3& wi) {
  return coatIsSpecular(coat) ? 0.0f : ggxDielectricReflectionPdf(coat, wo, wi);
}

std::optional<BsdfSample> coatSample(const Lobe& coat, const Vec3& wo, Vec2 u2) {
  if (!coatIsSpecular(coat)) {
    return ggxDielectricReflectionSample(coat, wo, u2);  // its f is coatEval's
  }
  const float cosO = std::fabs(wo.z);
  if (!(cosO >= kMinCosTheta)) return std::nullopt;
  BsdfSample s;
  s.specular = true;
  s.wi = Vec3(-wo.x, -wo.y, wo.z);
  s.pdfW = 1.0f;  // the mirror is the coat's only event; Bsdf multiplies its selection probability
  const float heroFresnel = usableEta(coat.a.v[0]) ? fresnelDielectric(cosO, coat.a.v[0]) : 0.0f;
  for (int i = 0; i < kLanes; ++i) {
    const float eta = laneEta(coat, i);
    if (coat.weight.v[i] == 0.0f || !usableEta(eta)) continue;
    s.f.v[i] = coat.weight.v[i] * (coat.etaVaries ? fresnelDielectric(cosO, eta) : heroFresnel) / cosO;
  }
  return s;
}

}  // namespace tex::render
