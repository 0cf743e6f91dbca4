// A point light of intensity I(lambda) (W/sr/nm, radiant intensity): radiance arriving from
// it at distance d is I / d^2 along one direction (a Dirac in position and in direction at
// the receiver), and it emits the same intensity in every direction.
#pragma once
#include <memory>

#include "renderer/lights/light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

class PointLight final : public Light {
 public:
  PointLight(const Vec3& position, SpectrumSource intensity) : position_(position), intensity_(std::move(intensity)) {}

  LightKind kind() const override { return LightKind::Point; }
  float power() const override;  // 4 pi I
  // A point (an empty box) emitting I in every direction: phi = I, theta_o = pi.
  std::optional<LightBounds> bounds() const override;
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3&, const Vec3&, const EmitterPoint*) const override { return 0.0f; }
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;

  Vec3 position() const { return position_; }

 private:
  Vec3 position_;
  SpectrumSource intensity_;
};

std::unique_ptr<Light> makePointLight(const Vec3& position, SpectrumSource intensity);

}  // namespace tex::render
