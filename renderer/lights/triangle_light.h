// A triangle that emits from the side of its normal: radiance from an EmissionSource (the
// surface's material) evaluated at the point with its interpolated uv. Next-event estimation
// samples the triangle uniformly by area; emitted directions are cosine-weighted.
#pragma once
#include <memory>

#include "renderer/lights/light.h"

namespace tex::render {

struct TriangleLightDesc {
  Vec3 p0{0.0f}, p1{0.0f}, p2{0.0f};  // world space
  Vec3 normal{0.0f};  // the emitting side (the face normal is flipped to agree); 0: winding
  int primitive = -1;  // reported in EmitterPoint::primitive
  int instance = -1;   // reported in EmitterPoint::instance (with `triangle`)
  uint32_t triangle = 0;
  // Emits from both faces (a double-sided glTF material): sampled, and its power counted, on
  // both (the back was reached by BSDF samples alone, 10x the error of the front).
  bool twoSided = false;
};

class TriangleLight final : public Light {
 public:
  // `emission` is not owned and must outlive the light.
  TriangleLight(const TriangleLightDesc& desc, const EmissionSource* emission);

  LightKind kind() const override { return LightKind::Triangle; }
  float power() const override;  // pi area averageRadiance per emitting side (Lambertian)
  // The triangle's box, its normal (theta_o = 0), Lambertian spread (theta_e = pi/2), and
  // phi = power / (pi sides): radiance x area of one face.
  std::optional<LightBounds> bounds() const override;
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  std::optional<LightLiSample> sampleLiDeferred(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  Spectrum deferredRadiance(const LightLiSample& sample, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const override;
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;

  // Radiance leaving `point` in direction `w` (zero on the back side), for paths that hit it.
  Spectrum L(const EmitterPoint& point, const Vec3& w, const Wavelengths& lambda) const;
  float area() const { return area_; }
  Vec3 normal() const { return n_; }
  // The point at barycentrics (b0, b1), with its uv.
  EmitterPoint pointAt(Vec2 b) const;

 private:
  void placeOnGeometry(EmitterPoint& e, Vec2 b) const;
  Vec2 barycentricsOf(const Vec3& p) const;
  TriangleLightDesc desc_;
  const EmissionSource* emission_;
  bool emissionReadsHit_ = false;
  Vec3 n_{0.0f};
  float area_ = 0;
  float pdfA_ = 0;  // 1 / area_, once rather than a division per light sample
  float pointError_ = 0;  // the largest axis of trianglePointError of the vertices: every sampled point's bound
};

std::unique_ptr<Light> makeTriangleLight(const TriangleLightDesc& desc, const EmissionSource* emission);

}  // namespace tex::render
