#include "renderer/lights/point_light.h"

#include <cmath>

#include "renderer/core/warp.h"

namespace tex::render {

float PointLight::power() const { return 4.0f * kPi * intensity_.luminance(); }

std::optional<LightBounds> PointLight::bounds() const {
  LightBounds b;
  b.box.extend(position_);
  b.phi = intensity_.luminance();
  b.normals = DirectionCone::entireSphere();
  b.cosThetaE = 0.0f;
  return b;
}

std::optional<LightLiSample> PointLight::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  (void)u;
  const Vec3 toLight = position_ - refPoint;
  const float dist2 = lengthSquared(toLight);
  if (!(dist2 > 0.0f)) return std::nullopt;
  LightLiSample s;
  s.distance = std::sqrt(dist2);
  s.wi = toLight / s.distance;
  s.pLight = position_;
  s.L = intensity_.sample(lambda) * (1.0f / dist2);
  s.pdfW = 1.0f;
  s.delta = true;
  return s;
}

std::optional<LightLeSample> PointLight::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  (void)uPos;
  LightLeSample s;
  s.ray.origin = position_;
  s.ray.direction = sampleUniformSphere(uDir);
  s.L = intensity_.sample(lambda);
  s.pdfPosA = 1.0f;  // Dirac position
  s.pdfDirW = kUniformSpherePdfW;
  return s;
}

void PointLight::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)ray;
  (void)nLight;
  pdfPosA = 1.0f;
  pdfDirW = kUniformSpherePdfW;
}

std::unique_ptr<Light> makePointLight(const Vec3& position, SpectrumSource intensity) {
  return std::make_unique<PointLight>(position, std::move(intensity));
}

}  // namespace tex::render
