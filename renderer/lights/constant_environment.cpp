#include "renderer/lights/constant_environment.h"

#include "renderer/core/warp.h"

namespace tex::render {

Ray environmentEmittedRay(const SceneSphere& sphere, const Vec3& wToLight, Vec2 uPos) {
  const Frame frame = Frame::fromNormal(wToLight);
  const Vec2 d = sampleConcentricDisk(uPos) * sphere.radius;
  Ray ray;
  ray.origin = sphere.center + frame.s * d.x + frame.t * d.y + wToLight * sphere.radius;
  ray.direction = -wToLight;
  return ray;
}

float ConstantEnvironment::power() const {
  return 4.0f * kPi * kPi * sphere_.radius * sphere_.radius * radiance_.luminance();
}

std::optional<LightLiSample> ConstantEnvironment::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  LightLiSample s;
  s.wi = sampleUniformSphere(u);
  s.pLight = refPoint + s.wi * (2.0f * sphere_.radius);
  s.distance = kInfinity;
  s.L = radiance_.sample(lambda);
  s.pdfW = kUniformSpherePdfW;
  return s;
}

float ConstantEnvironment::pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const {
  (void)refPoint;
  (void)wi;
  (void)onLight;
  return kUniformSpherePdfW;
}

std::optional<LightLeSample> ConstantEnvironment::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  const Vec3 wToLight = sampleUniformSphere(uDir);
  LightLeSample s;
  s.ray = environmentEmittedRay(sphere_, wToLight, uPos);
  s.nLight = -wToLight;
  s.L = radiance_.sample(lambda);
  s.pdfPosA = environmentDiskPdfA(sphere_);
  s.pdfDirW = kUniformSpherePdfW;
  return s;
}

void ConstantEnvironment::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)ray;
  (void)nLight;
  pdfPosA = environmentDiskPdfA(sphere_);
  pdfDirW = kUniformSpherePdfW;
}

Spectrum ConstantEnvironment::Le(const Ray& ray, const Wavelengths& lambda) const {
  (void)ray;
  return radiance_.sample(lambda);
}

std::unique_ptr<Light> makeConstantEnvironment(SpectrumSource radiance) {
  return std::make_unique<ConstantEnvironment>(std::move(radiance));
}

}  // namespace tex::render
