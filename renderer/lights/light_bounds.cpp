// Light bounds (light_bounds.h): cone unions and the importance of a bounded set of emitters at
// a reference point, after Conty Estevez and Kulla 2018 (section 4.1, eq. 3) and pbrt-v4's
// LightBounds::Importance.
#include "renderer/lights/light_bounds.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace tex::render {

namespace {

// Cosines are compared with this much slack so that rounding never makes the importance of a
// light that can contribute zero (a biased estimator); a light that cannot gets a tiny share.
constexpr float kCosSlack = 1e-4f;
// Cone unions are widened by this many radians against the rounding of acos / cos.
constexpr float kConeWiden = 1e-5f;

float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
float safeAcos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

// The angle between unit vectors, accurate near 0 and pi (asin of the half chord).
float angleBetween(const Vec3& a, const Vec3& b) {
  if (dot3(a, b) < 0.0f) return kPi - 2.0f * std::asin(std::min(glm::length(a + b) * 0.5f, 1.0f));
  return 2.0f * std::asin(std::min(glm::length(b - a) * 0.5f, 1.0f));
}

// cos(max(0, A - B)) and sin(max(0, A - B)) from the sines and cosines of A and B.
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
  if (cosA > cosB) return 1.0f;
  return cosA * cosB + sinA * sinB;
}
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
  if (cosA > cosB) return 0.0f;
  return sinA * cosB - cosA * sinB;
}

}  // namespace

DirectionCone unionCones(const DirectionCone& a, const DirectionCone& b) {
  // Equal axes (coplanar emitters, the common case): the wider cone, no trigonometry.
  if (a.w == b.w) return {a.w, std::min(a.cosTheta, b.cosTheta)};
  if (a.cosTheta <= -1.0f || b.cosTheta <= -1.0f) return DirectionCone::entireSphere();
  const float thetaA = safeAcos(a.cosTheta), thetaB = safeAcos(b.cosTheta);
  const float thetaD = angleBetween(a.w, b.w);
  if (std::min(thetaD + thetaB, kPi) <= thetaA) return a;
  if (std::min(thetaD + thetaA, kPi) <= thetaB) return b;
  const float thetaO = (thetaA + thetaD + thetaB) * 0.5f + kConeWiden;
  if (thetaO >= kPi) return DirectionCone::entireSphere();
  // Rotate a's axis toward b's by thetaO - thetaA about their common perpendicular.
  const Vec3 k = glm::cross(a.w, b.w);
  const float kLength = glm::length(k);
  if (!(kLength > 0.0f)) return DirectionCone::entireSphere();
  const float thetaR = thetaO - thetaA;
  const Vec3 w = glm::normalize(a.w * std::cos(thetaR) + glm::cross(k / kLength, a.w) * std::sin(thetaR));
  return {w, std::cos(thetaO)};
}

LightBounds unionBounds(const LightBounds& a, const LightBounds& b) {
  if (!(a.phi > 0.0f)) return b;
  if (!(b.phi > 0.0f)) return a;
  LightBounds u;
  u.box.lower = glm::min(a.box.lower, b.box.lower);
  u.box.upper = glm::max(a.box.upper, b.box.upper);
  u.phi = std::min(a.phi + b.phi, FLT_MAX);  // an overflowed sum still compares as the largest
  u.normals = unionCones(a.normals, b.normals);
  u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
  u.twoSided = a.twoSided || b.twoSided;
  return u;
}

float cosBoundSubtended(const Bounds3& box, const Vec3& p) {
  const Vec3 center = (box.lower + box.upper) * 0.5f;
  const float radius2 = 0.25f * lengthSquared(box.upper - box.lower);
  const float d2 = lengthSquared(p - center);
  if (!(d2 > radius2)) return -1.0f;
  return safeSqrt(1.0f - radius2 / d2);
}

float lightImportance(const LightSampleContext& ctx, const Vec3& lower, const Vec3& upper, float phi, const Vec3& w,
                      float cosThetaO, float cosThetaE, bool twoSided) {
  const Vec3 center = (lower + upper) * 0.5f;
  const float radius2 = 0.25f * lengthSquared(upper - lower);
  const Vec3 fromCenter = ctx.p - center;
  const float d2 = lengthSquared(fromCenter);
  // Inside the bounding sphere every direction may reach the box (theta_b = pi).
  const bool inside = !(d2 > radius2);
  const float cosThetaB = inside ? -1.0f : safeSqrt(1.0f - radius2 / d2);
  const float sinThetaB = safeSqrt(1.0f - cosThetaB * cosThetaB);
  const Vec3 wi = d2 > 0.0f ? fromCenter / std::sqrt(d2) : Vec3(0.0f);  // from the box toward p

  // The emitter's side: the smallest angle theta' between a normal in the cone (widened by
  // theta_b, the box's extent seen from p) and the direction toward p must be below theta_e.
  float cosThetaW = dot3(w, wi);
  if (twoSided) cosThetaW = std::fabs(cosThetaW);
  const float sinThetaW = safeSqrt(1.0f - cosThetaW * cosThetaW);
  const float sinThetaO = safeSqrt(1.0f - cosThetaO * cosThetaO);
  const float cosThetaX = cosSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
  const float sinThetaX = sinSubClamped(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
  const float cosThetaP = cosSubClamped(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
  if (cosThetaP <= cosThetaE - kCosSlack) return 0.0f;
  float importance = phi * std::max(cosThetaP, kCosSlack);

  // The receiver's side: one-sided in n (the directions a reflecting BSDF can use).
  if (ctx.n.x != 0.0f || ctx.n.y != 0.0f || ctx.n.z != 0.0f) {
    const float cosThetaI = -dot3(ctx.n, wi);
    const float sinThetaI = safeSqrt(1.0f - cosThetaI * cosThetaI);
    const float cosBound = cosSubClamped(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
    if (cosBound <= -kCosSlack) return 0.0f;
    importance *= std::max(cosBound, kCosSlack);
  }
  // Distance clamped below by the box's half-diagonal (Conty Estevez and Kulla: near or inside
  // a cluster its lights are not all close), and away from 0 for point lights.
  importance /= std::max({d2, radius2, 1e-30f});
  // Finite and comparable: sums of two importances must not overflow (1e30 + 1e30 < FLT_MAX).
  return importance >= 0.0f ? std::min(importance, 1e30f) : 0.0f;
}

}  // namespace tex::render
