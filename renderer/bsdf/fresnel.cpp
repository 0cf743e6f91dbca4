// Fresnel reflectance of dielectric and conductor interfaces (unpolarised light: the mean of
// the s- and p-polarised reflectances; Born & Wolf, "Principles of Optics", 1.5.2 and 14.2;
// pbrt-v4 section 9.3 and 9.5).
#include <algorithm>
#include <cmath>

#include "renderer/bsdf/bsdf.h"

namespace tex::render {

float fresnelDielectric(float cosThetaI, float eta) {
  if (eta == 1.0f) return 0.0f;  // index-matched: no interface (exactly, not ~1e-16 from rounding)
  if (!(eta > 0.0f)) return 1.0f;  // invalid IOR (0, negative, NaN): a mirror rather than NaN
  cosThetaI = std::clamp(cosThetaI, -1.0f, 1.0f);
  if (cosThetaI < 0.0f) {  // light arrives from inside: the interface seen the other way round
    eta = 1.0f / eta;
    cosThetaI = -cosThetaI;
  }
  const float sin2ThetaI = std::max(0.0f, 1.0f - cosThetaI * cosThetaI);
  const float sin2ThetaT = sin2ThetaI / (eta * eta);
  if (!(sin2ThetaT < 1.0f)) return 1.0f;  // total internal reflection (also catches eta = 0)
  const float cosThetaT = std::sqrt(1.0f - sin2ThetaT);
  const float rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
  const float rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
  return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

// Closed form of the exact complex Fresnel equations for n = eta + i k seen from a medium of
// index 1, written with real arithmetic so that the lane loop vectorises: a^2 + b^2 = |n^2 -
// sin^2|, a = Re sqrt(n^2 - sin^2) (Lagarde 2013, "Memo on Fresnel equations"; pbrt-v3 8.2.1).
Spectrum fresnelConductor(float cosThetaI, const Spectrum& eta, const Spectrum& k) {
  const float cosI = std::min(std::fabs(cosThetaI), 1.0f);
  const float cos2 = cosI * cosI;
  const float sin2 = 1.0f - cos2;
  Spectrum r;
  // A group of 4 wavelengths leaves lanes 4-7 of eta and k zero: their r stays 0 (evaluated,
  // n = 0 gives 1; either way the lobe's zero weight there makes f zero).
  const int lanes = eta.upperLanesZero() && k.upperLanesZero() ? 4 : kLanes;
  for (int i = 0; i < lanes; ++i) {
    const float eta2 = eta.v[i] * eta.v[i], k2 = k.v[i] * k.v[i];
    const float t0 = eta2 - k2 - sin2;
    const float a2PlusB2 = std::sqrt(std::max(0.0f, t0 * t0 + 4.0f * eta2 * k2));
    const float a = std::sqrt(std::max(0.0f, 0.5f * (a2PlusB2 + t0)));
    const float t1 = a2PlusB2 + cos2;
    const float t2 = 2.0f * cosI * a;
    // Denominators vanish only for n = 0 (unused lanes) or at grazing: the limit there is 1.
    const float rs = t1 + t2 > 0.0f ? (t1 - t2) / (t1 + t2) : 1.0f;
    const float t3 = cos2 * a2PlusB2 + sin2 * sin2;
    const float t4 = t2 * sin2;
    const float rp = t3 + t4 > 0.0f ? rs * (t3 - t4) / (t3 + t4) : rs;
    r.v[i] = 0.5f * (rs + rp);
  }
  return r;
}

}  // namespace tex::render
