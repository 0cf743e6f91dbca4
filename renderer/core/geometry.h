// Geometric basics shared by every renderer part: vectors (GLM), rays, orthonormal frames and
// robust ray origins. World space is right-handed, y up (glTF's convention), lengths in metres.
#pragma once
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace tex::render {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat4 = glm::mat4;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;
inline constexpr float kInv2Pi = 0.15915494309189533577f;
inline constexpr float kInv4Pi = 0.07957747154594766788f;
inline constexpr float kInfinity = INFINITY;

struct Ray {
  Vec3 origin{0.0f};
  Vec3 direction{0.0f, 0.0f, 1.0f};  // unit length unless a function says otherwise
  float tMax = kInfinity;
};

inline float dot3(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float absDot(const Vec3& a, const Vec3& b) { return std::fabs(dot3(a, b)); }
inline float lengthSquared(const Vec3& a) { return dot3(a, a); }

// An orthonormal basis; `n` is the local z axis ("up" of the local shading frame).
struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited": continuous except at one point.
  static Frame fromNormal(const Vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    Frame f;
    f.s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = Vec3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
  }
  // A frame with z = n and x as close as possible to `tangent` (Gram-Schmidt).
  static Frame fromNormalTangent(const Vec3& n, const Vec3& tangent) {
    Vec3 s = tangent - n * dot3(n, tangent);
    const float len2 = lengthSquared(s);
    if (!(len2 > 1e-12f)) return fromNormal(n);
    s /= std::sqrt(len2);
    Frame f;
    f.n = n;
    f.s = s;
    f.t = glm::cross(n, s);
    return f;
  }
  Vec3 toLocal(const Vec3& v) const { return {dot3(v, s), dot3(v, t), dot3(v, n)}; }
  Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Local-frame trigonometry (z is the normal).
inline float cosTheta(const Vec3& w) { return w.z; }
inline float absCosTheta(const Vec3& w) { return std::fabs(w.z); }
inline bool sameHemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0.0f; }

// The largest |coordinate| of v, NaN-free: a > m ? a : m keeps m for a NaN a, in maxss
// instructions (fmaxf was a libm call).
inline float maxAbsComponent(const Vec3& v, float atLeast = 0.0f) {
  float m = atLeast;
  const float ax = std::fabs(v.x), ay = std::fabs(v.y), az = std::fabs(v.z);
  m = ax > m ? ax : m;
  m = ay > m ? ay : m;
  m = az > m ? az : m;
  return m;
}

// How far a point interpolated on a triangle (b0 p0 + b1 p1 + b2 p2 in float, b >= 0) may be
// from the exact surface, per coordinate: pbrt-v4's gamma(7) sum |b_i p_i| <= gamma(7) max|p_i|
// (gamma(7) is about 7 float ulps, u = 2^-24), with room for an instance's transform (its world
// vertices are rounded, and Embree moves the ray into object space): kTrianglePointRelativeError
// of the largest |coordinate| among the vertices, per axis. It depends on the vertices, not on
// the point: a point near the origin on a huge triangle is as uncertain as its vertices are large.
constexpr float kTrianglePointRelativeError = 12.0f * 0x1p-24f;
// max(|a|, |b|, |c|) per coordinate (NaN-free by the same ternary as maxAbsComponent: maxss,
// where std::fmax is a libm call at -march=x86-64).
inline float maxAbs3(float a, float b, float c) {
  float m = std::fabs(a);
  const float fb = std::fabs(b), fc = std::fabs(c);
  m = fb > m ? fb : m;
  m = fc > m ? fc : m;
  return m;
}
// max(|a|, |b|) per coordinate (a already non-negative: a running maximum).
inline Vec3 absMaxPerAxis(const Vec3& a, const Vec3& b) {
  return Vec3(maxAbs3(a.x, b.x, 0.0f), maxAbs3(a.y, b.y, 0.0f), maxAbs3(a.z, b.z, 0.0f));
}
// The unit normal of a triangle with edges e1, e2, and the length of their cross product (twice
// its area); a zero normal and length for a degenerate triangle. In float when that length is a
// finite non-zero float with a normal (not denormal) square (the usual case); in double when
// the square overflows or leaves the normal range (edges beyond about 4e9, or below about 1e-10),
// which had made a zero or wrong normal (a black, unlit surface) or an infinite area.
inline Vec3 triangleUnitNormal(const Vec3& e1, const Vec3& e2, float& crossLength) {
  const Vec3 n = glm::cross(e1, e2);
  const float squared = lengthSquared(n);
  // A denormal square has lost its precision (a "unit" normal of length 0.7 at edges of 5e-12).
  if (squared >= std::numeric_limits<float>::min() && squared <= std::numeric_limits<float>::max()) {
    const float len = std::sqrt(squared);
    crossLength = len;
    return n / len;
  }
  const glm::dvec3 nd = glm::cross(glm::dvec3(e1), glm::dvec3(e2));
  const double lenD = glm::length(nd);
  if (!(lenD > 0.0) || !std::isfinite(lenD)) {
    crossLength = 0.0f;
    return Vec3(0.0f);
  }
  crossLength = float(lenD);
  return Vec3(nd / lenD);
}

inline Vec3 trianglePointError(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return kTrianglePointRelativeError *
         Vec3(maxAbs3(p0.x, p1.x, p2.x), maxAbs3(p0.y, p1.y, p2.y), maxAbs3(p0.z, p1.z, p2.z));
}

// Moves a ray origin off a surface along the geometric normal, past the point's error bound
// `pointError` (trianglePointError; pbrt-v4's OffsetRayOrigin), so that the new ray cannot hit
// the surface it leaves. `ng` (unit) need not face `direction`. The offset scales with the
// coordinates' float precision, not with |p|: scenes far from the origin keep their contacts
// and thin gaps (a relative epsilon of 1e-4 |p| moved origins by 2 units at 20000), and points
// near the origin of large triangles get the offset their vertices' magnitude needs.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& ng, const Vec3& direction, const Vec3& pointError) {
  const float d = std::fabs(ng.x) * pointError.x + std::fabs(ng.y) * pointError.y + std::fabs(ng.z) * pointError.z + 1e-30f;
  return p + ng * (dot3(ng, direction) >= 0.0f ? d : -d);
}

// Reflection of w about n (both unit; result points to the same side of n as... the mirror of w).
inline Vec3 reflect(const Vec3& w, const Vec3& n) { return -w + n * (2.0f * dot3(w, n)); }

}  // namespace tex::render
