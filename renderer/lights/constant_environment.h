// A uniform environment: radiance L(lambda) from every direction, sampled uniformly over the
// sphere. Emitted rays: a direction, then a point on a disk covering the scene sphere.
#pragma once
#include <memory>

#include "renderer/lights/light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

class ConstantEnvironment final : public Light {
 public:
  explicit ConstantEnvironment(SpectrumSource radiance) : radiance_(std::move(radiance)) {}

  LightKind kind() const override { return LightKind::ConstantEnvironment; }
  void preprocess(const SceneSphere& sphere) override { sphere_ = sphere; }
  float power() const override;  // 4 pi * pi R^2 * L
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const override;
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;
  Spectrum Le(const Ray& ray, const Wavelengths& lambda) const override;

 private:
  SpectrumSource radiance_;
  SceneSphere sphere_;
};

std::unique_ptr<Light> makeConstantEnvironment(SpectrumSource radiance);

// Emitted rays of a distant light arriving from `wToLight`: a point on the disk of the scene
// sphere's radius perpendicular to it, one radius upstream of the centre (pbrt-v4,
// ImageInfiniteLight::SampleLe). Shared by both environments.
Ray environmentEmittedRay(const SceneSphere& sphere, const Vec3& wToLight, Vec2 uPos);
inline float environmentDiskPdfA(const SceneSphere& sphere) { return 1.0f / (kPi * sphere.radius * sphere.radius); }

}  // namespace tex::render
