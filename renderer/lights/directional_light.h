// A distant light: irradiance E(lambda) (W/m^2/nm on a surface facing it) arriving from one
// direction. Emitted rays start on a disk that covers the scene's bounding sphere.
#pragma once
#include <memory>

#include "renderer/lights/light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

class DirectionalLight final : public Light {
 public:
  // `direction`: the direction light travels.
  DirectionalLight(const Vec3& direction, SpectrumSource irradiance);

  LightKind kind() const override { return LightKind::Directional; }
  void preprocess(const SceneSphere& sphere) override { sphere_ = sphere; }
  float power() const override;  // E over the disk that covers the scene: pi R^2 E
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3&, const Vec3&, const EmitterPoint*) const override { return 0.0f; }
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;

 private:
  Frame frame_;  // n = direction of travel
  SpectrumSource irradiance_;
  SceneSphere sphere_;
};

std::unique_ptr<Light> makeDirectionalLight(const Vec3& direction, SpectrumSource irradiance);

}  // namespace tex::render
