// Anisotropic GGX (Trowbridge-Reitz with alpha_x along the anisotropy axis and alpha_y across
// it; Heitz 2014 section 5.4 and 2018; pbrt-v4's TrowbridgeReitzDistribution). The axis is the
// lobe's local x axis turned by `rotation` radians about the normal (toward y).
// Every function dispatches to the isotropic one of microfacet.h when alpha_x == alpha_y, so
// isotropic lobes keep their arithmetic bit for bit (the rotation then changes nothing).
#pragma once
#include <cmath>

#include "renderer/core/geometry.h"

namespace tex::render {

struct GgxAlpha {
  float x = 0, y = 0;             // GGX alpha along the axis and across it
  float cosRot = 1, sinRot = 0;  // the axis in the local frame: (cosRot, sinRot, 0)
  GgxAlpha() = default;
  GgxAlpha(float alpha) : x(alpha), y(alpha) {}  // isotropic (implicit: every float alpha is one)
  GgxAlpha(float alphaX, float alphaY, float rotationRad)
      : x(alphaX), y(alphaY), cosRot(std::cos(rotationRad)), sinRot(std::sin(rotationRad)) {}
  bool isotropic() const { return x == y; }
  // A local direction in the frame whose x axis is the anisotropy axis, and back.
  Vec3 toAxes(const Vec3& v) const { return {cosRot * v.x + sinRot * v.y, -sinRot * v.x + cosRot * v.y, v.z}; }
  Vec3 fromAxes(const Vec3& v) const { return {cosRot * v.x - sinRot * v.y, sinRot * v.x + cosRot * v.y, v.z}; }
};

// Two different alphas only (the GgxAlpha overloads in microfacet.h dispatch, inline, so that
// isotropic lobes pay no call for the choice).
float ggxDAnisotropic(const Vec3& m, const GgxAlpha& alpha);
float ggxLambdaAnisotropic(const Vec3& w, const GgxAlpha& alpha);
float ggxVisibleDAnisotropic(const Vec3& w, const Vec3& m, const GgxAlpha& alpha);
Vec3 ggxSampleVisibleNormalAnisotropic(const Vec3& w, const GgxAlpha& alpha, Vec2 u);

}  // namespace tex::render
