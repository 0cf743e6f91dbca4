// Warps from uniform numbers in [0,1)^n to distributions on common domains, each with its
// density in the measure named by the function (standard results; see pbrt-v4, chapter A.5,
// and Shirley & Chiu 1997 for the concentric disk map).
#pragma once
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "renderer/core/geometry.h"

namespace tex::render {

// sin and cos of x for |x| <= pi/4: Cephes' sinf/cosf polynomials (S. Moshier), inline. Over
// every float x = (pi/4) t, t in [-1, 1], they are within 0.49 ulp of 1.0 of double sin/cos
// (glibc's sincosf: 0.27); the call to sincosf, its spills and its range reduction were 2 % of a
// Cornell render at the baseline x86-64 (no FMA) build.
inline Vec2 cosSinQuarterPi(float x) {
  const float x2 = x * x;
  const float sinX = ((-1.9515295891e-4f * x2 + 8.3321608736e-3f) * x2 - 1.6666654611e-1f) * x2 * x + x;
  const float cosX =
      ((2.443315711809948e-5f * x2 - 1.388731625493765e-3f) * x2 + 4.166664568298827e-2f) * (x2 * x2) - 0.5f * x2 + 1.0f;
  return Vec2(cosX, sinX);
}

// Unit disk, area density 1/pi. Concentric (low distortion, keeps stratification).
inline Vec2 sampleConcentricDisk(Vec2 u) {
  const Vec2 o = u * 2.0f - Vec2(1.0f);
  if (o.x == 0.0f && o.y == 0.0f) return Vec2(0.0f);
  if (std::fabs(o.x) > std::fabs(o.y)) {
    // r = o.x, theta = (pi/4) (o.y / o.x).
    const Vec2 cs = cosSinQuarterPi((kPi / 4.0f) * (o.y / o.x));
    return Vec2(o.x * cs.x, o.x * cs.y);
  }
  // r = o.y, theta = pi/2 - x with x = (pi/4) (o.x / o.y): cos(theta) = sin(x), sin(theta) = cos(x).
  const Vec2 cs = cosSinQuarterPi((kPi / 4.0f) * (o.x / o.y));
  return Vec2(o.y * cs.y, o.y * cs.x);
}

// Cosine-weighted hemisphere around +z: pdfW = cos(theta) / pi.
inline Vec3 sampleCosineHemisphere(Vec2 u) {
  const Vec2 d = sampleConcentricDisk(u);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return Vec3(d.x, d.y, z);
}
inline float cosineHemispherePdfW(float cosTheta) { return cosTheta > 0.0f ? cosTheta * kInvPi : 0.0f; }

// Uniform sphere: pdfW = 1 / (4 pi).
inline Vec3 sampleUniformSphere(Vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}
inline constexpr float kUniformSpherePdfW = kInv4Pi;

// Uniform hemisphere around +z: pdfW = 1 / (2 pi).
inline Vec3 sampleUniformHemisphere(Vec2 u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}
inline constexpr float kUniformHemispherePdfW = kInv2Pi;

// Uniform cone around +z with half-angle acos(cosThetaMax): pdfW = 1 / (2 pi (1 - cosThetaMax)).
inline Vec3 sampleUniformCone(Vec2 u, float cosThetaMax) {
  const float cosTheta = (1.0f - u.x) + u.x * cosThetaMax;
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float phi = 2.0f * kPi * u.y;
  return Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
}
inline float uniformConePdfW(float cosThetaMax) { return 1.0f / (2.0f * kPi * (1.0f - cosThetaMax)); }

// Uniform barycentrics on a triangle (b0, b1; b2 = 1 - b0 - b1): area density 1 / area.
// Heitz 2019's square-to-triangle map (keeps stratification better than the sqrt map).
// The smaller coordinate is halved and the other loses that half: u.x < u.y ? (u.x / 2,
// u.y - u.x / 2) : (u.x - u.y / 2, u.y / 2). Without a branch (minss, maxss and a mask select,
// the same values bit for bit): the comparison is a coin flip at every light sample, and its
// mispredictions cost more than computing both sides.
inline Vec2 sampleUniformTriangle(Vec2 u) {
#if defined(__SSE2__)
  const __m128 ux = _mm_set_ss(u.x), uy = _mm_set_ss(u.y);
  const __m128 xFirst = _mm_cmplt_ss(ux, uy);
  const __m128 half = _mm_mul_ss(_mm_min_ss(ux, uy), _mm_set_ss(0.5f));  // minss: ux < uy ? ux : uy
  const __m128 rest = _mm_sub_ss(_mm_max_ss(uy, ux), half);              // maxss: uy > ux ? uy : ux
  const __m128 b0 = _mm_or_ps(_mm_and_ps(xFirst, half), _mm_andnot_ps(xFirst, rest));
  const __m128 b1 = _mm_or_ps(_mm_and_ps(xFirst, rest), _mm_andnot_ps(xFirst, half));
  return Vec2(_mm_cvtss_f32(b0), _mm_cvtss_f32(b1));
#else
  if (u.x < u.y) return Vec2(u.x * 0.5f, u.y - u.x * 0.5f);
  return Vec2(u.x - u.y * 0.5f, u.y * 0.5f);
#endif
}

// Converts a density per unit area at a point seen from a reference point to a density per
// solid angle there: pdfW = pdfA * distance^2 / |cos at the point|.
inline float areaToSolidAnglePdf(float pdfA, float distanceSquared, float absCosAtPoint) {
  return absCosAtPoint > 0.0f ? pdfA * distanceSquared / absCosAtPoint : 0.0f;
}

// The power heuristic (exponent 2) for multiple importance sampling (Veach 1997).
inline float powerHeuristic(float pdfA, float pdfB) {
  const float a = pdfA * pdfA, b = pdfB * pdfB;
  if (std::isinf(a)) return 1.0f;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// Direction <-> spherical coordinates, with theta measured from +y (world up) for environment
// maps: u = phi / 2pi in [0,1), v = theta / pi in [0,1] (v = 0 straight up).
inline Vec3 sphericalDirectionYUp(float u, float v) {
  const float phi = 2.0f * kPi * u, theta = kPi * v;
  const float s = std::sin(theta);
  return Vec3(s * std::sin(phi), std::cos(theta), -s * std::cos(phi));
}
inline Vec2 directionToSphericalYUp(const Vec3& d) {
  const float theta = std::acos(std::clamp(d.y, -1.0f, 1.0f));
  float phi = std::atan2(d.x, -d.z);
  if (phi < 0.0f) phi += 2.0f * kPi;
  return Vec2(phi * kInv2Pi, theta * kInvPi);
}

}  // namespace tex::render
