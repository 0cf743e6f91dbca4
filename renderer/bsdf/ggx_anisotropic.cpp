// Anisotropic GGX: D, Smith Lambda and visible-normal sampling with two alphas (Heitz 2014
// eq. 85 and 86; Heitz 2018: the anisotropic stretch is (alpha_x w.x, alpha_y w.y, w.z)).
// Isotropic alphas take microfacet.cpp's code unchanged (microfacet.h dispatches).
#include "renderer/bsdf/ggx_anisotropic.h"

#include <algorithm>

#include "renderer/bsdf/microfacet.h"

namespace tex::render {

float ggxDAnisotropic(const Vec3& m, const GgxAlpha& alpha) {
  if (!(m.z > 0.0f)) return 0.0f;
  // D = 1 / (pi ax ay (x^2 / ax^2 + y^2 / ay^2 + z^2)^2) for a unit m in the anisotropy axes.
  const Vec3 a = alpha.toAxes(m);
  const float e = a.x * a.x / (alpha.x * alpha.x) + a.y * a.y / (alpha.y * alpha.y) + a.z * a.z;
  return 1.0f / (kPi * alpha.x * alpha.y * e * e);
}

float ggxLambdaAnisotropic(const Vec3& w, const GgxAlpha& alpha) {
  const float cos2 = w.z * w.z;
  if (!(cos2 > 0.0f)) return INFINITY;
  const Vec3 a = alpha.toAxes(w);
  // alpha(phi)^2 tan^2 = (ax^2 x^2 + ay^2 y^2) / z^2: the projected roughness along w.
  const float a2Tan2 = (alpha.x * alpha.x * a.x * a.x + alpha.y * alpha.y * a.y * a.y) / cos2;
  return 0.5f * a2Tan2 / (std::sqrt(1.0f + a2Tan2) + 1.0f);
}

float ggxVisibleDAnisotropic(const Vec3& w, const Vec3& m, const GgxAlpha& alpha) {
  const float cosW = std::fabs(w.z);
  if (!(cosW > 0.0f)) return 0.0f;
  return std::fabs(dot3(w, m)) * ggxDAnisotropic(m, alpha) / ((1.0f + ggxLambdaAnisotropic(w, alpha)) * cosW);
}

Vec3 ggxSampleVisibleNormalAnisotropic(const Vec3& w, const GgxAlpha& alpha, Vec2 u) {
  // As the isotropic sampler, in the anisotropy axes, with a stretch per axis.
  const Vec3 wu = alpha.toAxes(w.z < 0.0f ? -w : w);
  const Vec3 nh = visibleHemisphereNormal(glm::normalize(Vec3(alpha.x * wu.x, alpha.y * wu.y, wu.z)), u);
  const Vec3 ne(alpha.x * nh.x, alpha.y * nh.y, std::max(1e-6f, nh.z));
  return alpha.fromAxes(glm::normalize(ne));
}

}  // namespace tex::render
