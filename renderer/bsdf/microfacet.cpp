// GGX distribution, Smith masking and visible-normal sampling (formulas: Walter et al. 2007,
// Heitz 2014 and 2018; pbrt-v4 section 9.6). Written for robustness near the normal and at
// grazing: the denominators use sin^2 rather than 1 - cos^2.
#include <algorithm>
#include <cmath>

#include "renderer/bsdf/microfacet.h"

namespace tex::render {

float clampGgxAlpha(float alpha) {
  if (!(alpha >= kMinGgxAlpha)) return kMinGgxAlpha;  // also NaN
  return std::min(alpha, 1e3f);
}

float ggxD(const Vec3& m, float alpha) {
  if (!(m.z > 0.0f)) return 0.0f;
  // D = 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2) = 1 / (pi a^2 (sin^2 / a^2 + cos^2)^2).
  const float sin2 = m.x * m.x + m.y * m.y;
  const float e = sin2 / (alpha * alpha) + m.z * m.z;
  return 1.0f / (kPi * alpha * alpha * e * e);
}

float ggxLambda(const Vec3& w, float alpha) {
  const float cos2 = w.z * w.z;
  if (!(cos2 > 0.0f)) return INFINITY;  // grazing: fully masked
  const float a2Tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / cos2;
  // (sqrt(1 + x) - 1) / 2 written without cancellation for small x.
  return 0.5f * a2Tan2 / (std::sqrt(1.0f + a2Tan2) + 1.0f);
}

float ggxVisibleD(const Vec3& w, const Vec3& m, float alpha) {
  const float cosW = std::fabs(w.z);
  if (!(cosW > 0.0f)) return 0.0f;
  return ggxG1(w, alpha) * std::fabs(dot3(w, m)) * ggxD(m, alpha) / cosW;
}

Vec3 ggxSampleVisibleNormal(const Vec3& w, float alpha, Vec2 u) {
  // Heitz 2018: stretch to the hemisphere configuration (alpha = 1), sample the projected
  // area of the hemisphere seen from the stretched view direction, unstretch.
  // From below, the point reflection -w sees the same microsurface from above; then w.m < 0
  // for the sampled m, as refraction out of the lower side needs.
  const Vec3 wu = w.z < 0.0f ? -w : w;
  const Vec3 nh = visibleHemisphereNormal(glm::normalize(Vec3(alpha * wu.x, alpha * wu.y, wu.z)), u);
  const Vec3 ne(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z));
  return glm::normalize(ne);
}

}  // namespace tex::render
