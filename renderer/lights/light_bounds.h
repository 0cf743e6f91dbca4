// Spatial and directional bounds of a light's emission, for choosing lights by their likely
// contribution at a reference point (the light BVH, light_bvh.h). After Conty Estevez and
// Kulla 2018, "Importance Sampling of Many Lights with Adaptive Tree Splitting", section 4,
// and pbrt-v4's LightBounds: a box holding the emitter, a cone of its emitting normals (axis w,
// half-angle theta_o) and the spread of emission about each normal (theta_e: pi/2 for a
// Lambertian surface), a scalar power phi and whether it emits from both faces.
#pragma once
#include <algorithm>
#include <cmath>

#include "renderer/core/geometry.h"
#include "renderer/scene/load_scene.h"

namespace tex::render {

// A cone of directions: axis w (unit), cosTheta the cosine of its half-angle (-1: every
// direction).
struct DirectionCone {
  Vec3 w{0.0f, 0.0f, 1.0f};
  float cosTheta = 1.0f;
  static DirectionCone entireSphere() { return {Vec3(0.0f, 0.0f, 1.0f), -1.0f}; }
};
// The smallest cone (up to a small widening against rounding) holding both.
DirectionCone unionCones(const DirectionCone& a, const DirectionCone& b);

// Where importance is judged: the shading point and the normal that bounds the receiver's
// cosine factor. n points to the side whose directions can contribute (a reflecting BSDF: wo's
// side); n = 0 means "no normal" (a transmitting BSDF, or a point in a medium).
struct LightSampleContext {
  Vec3 p{0.0f};
  Vec3 n{0.0f};
};

struct LightBounds {
  Bounds3 box;
  // A radiant-intensity-like scale (W/sr in the power() proxy's units): importance is
  // phi * cos bounds / distance^2, an estimate of irradiance. Triangles: radiance x area (one
  // face); point and spot lights: their intensity on the axis.
  float phi = 0.0f;
  DirectionCone normals;  // theta_o: bounds the emitting normals (spot: the axis)
  float cosThetaE = 0.0f;  // theta_e: emission spread about a normal (Lambertian: pi/2)
  bool twoSided = false;   // emits around -w too
};

LightBounds unionBounds(const LightBounds& a, const LightBounds& b);

// Cosines are compared with this much slack so that rounding never makes the importance of a
// light that can contribute zero (a biased estimator for Dirac lights); a light that cannot
// gets a tiny share.
inline constexpr float kImportanceCosSlack = 1e-4f;

// An estimate of what a light inside the bounds can contribute at ctx, relative to others
// (Conty Estevez and Kulla, eq. 3 with the receiver's cosine bound; pbrt-v4
// LightBounds::Importance, but one-sided in n). Conservative: positive whenever some point of
// the sphere (center, radius), with a normal in the cone (w, theta_o), emits toward p and lies on
// n's side of p (n = 0: any side). Inline, with the sphere and the cone's sine precomputed:
// the light BVH evaluates two per level, and their square roots overlap.
inline float lightImportance(const LightSampleContext& ctx, const Vec3& center, float radius, const Vec3& w, float phi,
                             float cosThetaO, float sinThetaO, float cosThetaE, bool twoSided) {
  // Written without early returns (selects instead): at random shading points every test is a
  // coin flip, and mispredicted branches were most of a descent's cost.
  const Vec3 fromCenter = ctx.p - center;
  const float d2 = dot3(fromCenter, fromCenter);
  const float r2 = radius * radius;
  // Inside the bounding sphere every direction may reach the box: theta_b = pi, which turns
  // both cosine bounds below into 1. The distance is clamped to the radius (near or inside a
  // cluster its lights are not all close: Conty Estevez and Kulla).
  const bool inside = !(d2 > r2);
  const float invD = 1.0f / std::sqrt(std::max(d2, 1e-30f));
  const Vec3 wi = fromCenter * invD;  // from the box toward p
  const float sinThetaB = inside ? 0.0f : std::min(radius * invD, 1.0f);
  const float cosThetaB = inside ? -1.0f : std::sqrt(std::max(0.0f, 1.0f - sinThetaB * sinThetaB));
  // cos(max(0, A - B)) and sin(max(0, A - B)) from the sines and cosines of A and B.
  const auto cosSub = [](float sinA, float cosA, float sinB, float cosB) { return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB; };
  const auto sinSub = [](float sinA, float cosA, float sinB, float cosB) { return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB; };

  // The emitter's side: the smallest angle theta' between a normal in the cone and a direction
  // toward p from the box (theta_w - theta_o - theta_b) must be below theta_e.
  float cosThetaW = dot3(w, wi);
  cosThetaW = twoSided ? std::fabs(cosThetaW) : cosThetaW;
  const float sinThetaW = std::sqrt(std::max(0.0f, 1.0f - cosThetaW * cosThetaW));
  const float cosThetaX = cosSub(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
  const float sinThetaX = sinSub(sinThetaW, cosThetaW, sinThetaO, cosThetaO);
  const float cosThetaP = cosSub(sinThetaX, cosThetaX, sinThetaB, cosThetaB);
  const bool emitsToward = cosThetaP > cosThetaE - kImportanceCosSlack;

  // The receiver's side: one-sided in n (the directions a reflecting BSDF can use).
  const bool hasNormal = ctx.n.x != 0.0f || ctx.n.y != 0.0f || ctx.n.z != 0.0f;
  const float cosThetaI = -dot3(ctx.n, wi);
  const float sinThetaI = std::sqrt(std::max(0.0f, 1.0f - cosThetaI * cosThetaI));
  const float cosBound = cosSub(sinThetaI, cosThetaI, sinThetaB, cosThetaB);
  const bool inFront = !hasNormal || cosBound > -kImportanceCosSlack;
  const float receiver = hasNormal ? std::max(cosBound, kImportanceCosSlack) : 1.0f;

  const float importance = phi * std::max(cosThetaP, kImportanceCosSlack) * receiver / std::max({d2, r2, 1e-30f});
  // Finite and comparable: sums of two importances must not overflow (1e30 + 1e30 < FLT_MAX).
  return emitsToward && inFront && importance >= 0.0f ? std::min(importance, 1e30f) : 0.0f;
}

// The bounding sphere of a box, its radius rounded up so that it holds every corner.
inline void boundingSphere(const Bounds3& box, Vec3& center, float& radius) {
  center = (box.lower + box.upper) * 0.5f;
  radius = 0.5f * std::sqrt(dot3(box.upper - box.lower, box.upper - box.lower)) * (1.0f + 1e-6f);
}

inline float lightImportance(const LightSampleContext& ctx, const LightBounds& b) {
  Vec3 center;
  float radius;
  boundingSphere(b.box, center, radius);
  const float cosO = std::clamp(b.normals.cosTheta, -1.0f, 1.0f);
  return lightImportance(ctx, center, radius, b.normals.w, b.phi, cosO, std::sqrt(std::max(0.0f, 1.0f - cosO * cosO)),
                         b.cosThetaE, b.twoSided);
}

}  // namespace tex::render
