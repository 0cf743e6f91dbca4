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
  angleScale_ = 1.0f / std::max(0.001f, std::cos(inner) - cosOuter_);  // KHR_lights_punctual
}

float SpotLight::falloff(const Vec3& wOut) const {
  const float t = std::clamp((dot3(wOut, frame_.n) - cosOuter_) * angleScale_, 0.0f, 1.0f);
  return t * t;
}

float SpotLight::power() const {
  // 2 pi times the integral of the falloff over cos: 1 above cosFull, the quadratic ramp
  // integrates to s^2 (m - cosOuter)^3 / 3 between cosOuter and m = min(1, cosFull).
  const float cosFull = std::min(1.0f, cosOuter_ + 1.0f / angleScale_);
  const float ramp = cosFull - cosOuter_;
  const float integral = (1.0f - cosFull) + angleScale_ * angleScale_ * ramp * ramp * ramp / 3.0f;
  return 2.0f * kPi * integral * intensity_.luminance();
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
