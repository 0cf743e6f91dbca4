// Geometric basics shared by every renderer part: vectors (GLM), rays, orthonormal frames and
// robust ray origins. World space is right-handed, y up (glTF's convention), lengths in metres.
#pragma once
#include <cmath>

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

// Moves a ray origin off a surface along the geometric normal, far enough that the new ray
// does not hit the surface it leaves, in a way that scales with the magnitude of the
// coordinates (a relative epsilon: float rounding of a hit point grows with |p|, so a fixed
// epsilon fails on both tiny and huge scenes). `ng` need not face `direction`.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& ng, const Vec3& direction) {
  // std::fmax(std::fmax(std::fmax(|x|, |y|), |z|), 1e-3) is the largest of the values that are
  // not NaN (fmax drops a NaN operand), 1e-3 included: a > m ? a : m keeps m for a NaN a and,
  // with m starting from 1e-3, is that maximum, in maxss instructions (fmaxf was a libm call).
  float magnitude = 1e-3f;
  const float ax = std::fabs(p.x), ay = std::fabs(p.y), az = std::fabs(p.z);
  magnitude = ax > magnitude ? ax : magnitude;
  magnitude = ay > magnitude ? ay : magnitude;
  magnitude = az > magnitude ? az : magnitude;
  const float eps = 1e-4f * magnitude + 1e-7f;
  const Vec3 offset = ng * (dot3(ng, direction) >= 0.0f ? eps : -eps);
  return p + offset;
}

// Reflection of w about n (both unit; result points to the same side of n as... the mirror of w).
inline Vec3 reflect(const Vec3& w, const Vec3& n) { return -w + n * (2.0f * dot3(w, n)); }

}  // namespace tex::render
