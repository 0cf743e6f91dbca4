#include "renderer/lights/directional_light.h"

#include <cmath>

#include "renderer/core/warp.h"

namespace tex::render {

DirectionalLight::DirectionalLight(const Vec3& direction, SpectrumSource irradiance)
    : frame_(Frame::fromNormal(glm::normalize(direction))), irradiance_(std::move(irradiance)) {}

float DirectionalLight::power() const {
  return kPi * sphere_.radius * sphere_.radius * irradiance_.luminance();
}

std::optional<LightLiSample> DirectionalLight::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  (void)u;
  LightLiSample s;
  s.wi = -frame_.n;
  s.pLight = refPoint + s.wi * (2.0f * sphere_.radius);  // outside the scene
  s.distance = kInfinity;
  s.L = irradiance_.sample(lambda);
  s.pdfW = 1.0f;
  s.delta = true;
  return s;
}

std::optional<LightLeSample> DirectionalLight::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  (void)uDir;
  // A disk of the scene's radius, perpendicular to the light, one radius upstream of the centre.
  const Vec2 d = sampleConcentricDisk(uPos) * sphere_.radius;
  LightLeSample s;
  s.ray.origin = sphere_.center + frame_.s * d.x + frame_.t * d.y - frame_.n * sphere_.radius;
  s.ray.direction = frame_.n;
  s.nLight = frame_.n;
  s.L = irradiance_.sample(lambda);
  s.pdfPosA = 1.0f / (kPi * sphere_.radius * sphere_.radius);
  s.pdfDirW = 1.0f;  // Dirac direction
  return s;
}

void DirectionalLight::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)ray;
  (void)nLight;
  pdfPosA = 1.0f / (kPi * sphere_.radius * sphere_.radius);
  pdfDirW = 1.0f;  // Dirac direction (as in sampleLe)
}

std::unique_ptr<Light> makeDirectionalLight(const Vec3& direction, SpectrumSource irradiance) {
  return std::make_unique<DirectionalLight>(direction, std::move(irradiance));
}

}  // namespace tex::render
