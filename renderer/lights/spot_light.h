// A spot light: a point light of intensity I(lambda) W/sr on its axis, attenuated away from the
// axis by the falloff of glTF's KHR_lights_punctual (scenes come from glTF, so a glTF viewer
// and this renderer light a scene the same way). With c = cos(angle to the axis),
//   falloff(c) = clamp((c - cos(outer)) / (cos(inner) - cos(outer)), 0, 1)^2:
// full intensity inside the inner cone, quadratic in cos down to 0 at the outer cone, as the
// Khronos sample viewer computes it. The spec's pseudocode bounds the denominator below by
// 0.001, which left cones narrower than about 2.5 degrees dim on their own axis (2 % of the
// intensity at 1 degree); here the differences are taken as 1 - cos, exact for narrow cones.
// (pbrt-v4 uses smoothstep(cos(outer), cos(inner), c) instead; they differ in the penumbra.)
#pragma once
#include <memory>

#include "renderer/lights/light.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

class SpotLight final : public Light {
 public:
  // `direction`: where the light points (the direction light travels on the axis).
  SpotLight(const Vec3& position, const Vec3& direction, SpectrumSource intensity, float innerConeRadians,
            float outerConeRadians);

  LightKind kind() const override { return LightKind::Spot; }
  float power() const override;
  // A point emitting up to I along its axis: phi = I, theta_o = 0, theta_e = the outer cone.
  std::optional<LightBounds> bounds() const override;
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3&, const Vec3&, const EmitterPoint*) const override { return 0.0f; }
  // Directions uniform in the outer cone.
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;

  // The glTF falloff for a direction leaving the light (unit vector, world space).
  float falloff(const Vec3& wOut) const;

 private:
  Vec3 position_;
  Frame frame_;  // n = axis
  SpectrumSource intensity_;
  float cosOuter_ = 0;                          // for sampling the outer cone
  float versineOuter_ = 1, versineInner_ = 0;  // 1 - cos of the cone angles
};

std::unique_ptr<Light> makeSpotLight(const Vec3& position, const Vec3& direction, SpectrumSource intensity,
                                     float innerConeRadians, float outerConeRadians);

}  // namespace tex::render
