#include "renderer/lights/spot_light.h"

#include <algorithm>
#include <cmath>

#include "renderer/core/warp.h"

namespace tex::render {

SpotLight::SpotLight(const Vec3& position, const Vec3& direction, SpectrumSource intensity, float innerConeRadians,
                     float outerConeRadians)
    : position_(position), frame_(Frame::fromNormal(glm::normalize(direction))), intensity_(std::move(intensity)) {
  const float outer = std::clamp(outerConeRadians, 0.0f, kPi / 2.0f);  // glTF: outer <= pi/2
  const float inner = std::clamp(innerConeRadians, 0.0f, outer);
  cosOuter_ = std::cos(outer);
  // 1 - cos as 2 sin^2(angle / 2): exact for narrow cones, where cos rounds to 1.
  const auto versine = [](float angle) {
    const float s = std::sin(0.5f * angle);
    return 2.0f * s * s;
  };
  versineOuter_ = versine(outer);
  versineInner_ = versine(inner);
}

float SpotLight::falloff(const Vec3& wOut) const {
  // 1 - c = |n x w|^2 / (1 + c) keeps its precision near the axis, where c itself rounds to 1.
  const float c = dot3(wOut, frame_.n);
  if (!(c > 0.0f)) return 0.0f;  // outer <= pi/2
  const float versine = lengthSquared(glm::cross(frame_.n, wOut)) / (1.0f + c);
  if (!(versine < versineOuter_)) return 0.0f;
  const float band = versineOuter_ - versineInner_;
  if (!(versine > versineInner_) || !(band > 0.0f)) return 1.0f;
  const float t = std::min((versineOuter_ - versine) / band, 1.0f);
  return t * t;
}

float SpotLight::power() const {
  // 2 pi times the integral of the falloff over cos (v = 1 - cos): 1 inside the inner cone
  // (v_inner), and the quadratic ramp integrates to (v_outer - v_inner) / 3.
  const float integral = versineInner_ + (versineOuter_ - versineInner_) / 3.0f;
  return 2.0f * kPi * integral * intensity_.luminance();
}

std::optional<LightBounds> SpotLight::bounds() const {
  LightBounds b;
  b.box.extend(position_);
  b.phi = intensity_.luminance();
  b.normals = {frame_.n, 1.0f};
  b.cosThetaE = 1.0f - versineOuter_;
  return b;
}

std::optional<LightLiSample> SpotLight::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  (void)u;
  const Vec3 toLight = position_ - refPoint;
  const float dist2 = lengthSquared(toLight);
  if (!(dist2 > 0.0f)) return std::nullopt;
  const float dist = std::sqrt(dist2);
  const Vec3 wi = toLight / dist;
  const float f = falloff(-wi);
  if (f == 0.0f) return std::nullopt;
  LightLiSample s;
  s.distance = dist;
  s.wi = wi;
  s.pLight = position_;
  s.L = intensity_.sample(lambda) * (f / dist2);
  s.pdfW = 1.0f;
  s.delta = true;
  return s;
}

std::optional<LightLeSample> SpotLight::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  (void)uPos;
  const Vec3 w = frame_.toWorld(sampleUniformCone(uDir, cosOuter_));
  const float f = falloff(w);
  if (f == 0.0f) return std::nullopt;
  LightLeSample s;
  s.ray.origin = position_;
  s.ray.direction = w;
  s.L = intensity_.sample(lambda) * f;
  s.pdfPosA = 1.0f;
  s.pdfDirW = uniformConePdfW(cosOuter_);
  return s;
}

void SpotLight::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)nLight;
  pdfPosA = 1.0f;
  pdfDirW = dot3(ray.direction, frame_.n) >= cosOuter_ ? uniformConePdfW(cosOuter_) : 0.0f;
}

std::unique_ptr<Light> makeSpotLight(const Vec3& position, const Vec3& direction, SpectrumSource intensity,
                                     float innerConeRadians, float outerConeRadians) {
  return std::make_unique<SpotLight>(position, direction, std::move(intensity), innerConeRadians, outerConeRadians);
}

}  // namespace tex::render
