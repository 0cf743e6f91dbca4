// Light bounds (light_bounds.h): unions of bounds and of direction cones (pbrt-v4's
// DirectionCone Union).
#include "renderer/lights/light_bounds.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace tex::render {

namespace {

// Cone unions are widened by this many radians against the rounding of acos / cos.
constexpr float kConeWiden = 1e-5f;

float safeAcos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

// The angle between unit vectors, accurate near 0 and pi (asin of the half chord).
float angleBetween(const Vec3& a, const Vec3& b) {
  if (dot3(a, b) < 0.0f) return kPi - 2.0f * std::asin(std::min(glm::length(a + b) * 0.5f, 1.0f));
  return 2.0f * std::asin(std::min(glm::length(b - a) * 0.5f, 1.0f));
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

}  // namespace tex::render
