// An environment map: a latitude-longitude image (top row straight up, +y; u = phi / 2pi with
// the mapping of warp.h's sphericalDirectionYUp) whose linear sRGB pixels are radiances,
// upsampled as illuminants. Each pixel is constant over its patch of the sphere, and
// directions are importance-sampled by a 2D piecewise-constant distribution proportional to
// luminance x the pixel's solid angle (marginal over rows, conditional over columns; inside a
// pixel uniform in phi and cos(theta)), so the density of a direction is luminance / integral
// and pdf and Le agree exactly.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "renderer/image/image_io.h"
#include "renderer/lights/light.h"
#include "renderer/lights/piecewise_constant.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

class ImageEnvironment final : public Light {
 public:
  // `environmentToWorld`: only its rotation is used. `scale` multiplies every pixel.
  ImageEnvironment(const RgbImage& image, const Mat4& environmentToWorld, float scale = 1.0f);

  LightKind kind() const override { return LightKind::ImageEnvironment; }
  void preprocess(const SceneSphere& sphere) override { sphere_ = sphere; }
  float power() const override;  // pi R^2 times the luminance integrated over the sphere
  std::optional<LightLiSample> sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const override;
  float pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const override;
  std::optional<LightLeSample> sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const override;
  void pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const override;
  Spectrum Le(const Ray& ray, const Wavelengths& lambda) const override;

  // Luminance integrated over the sphere (W/m^2/sr * sr, luminance units).
  float luminanceIntegral() const { return luminanceIntegral_; }
  // Pixels with a NaN, infinite or negative channel (they emit nothing), for a warning.
  uint64_t droppedPixels() const { return droppedPixels_; }

 private:
  struct Pixel {
    int x = 0, y = 0;
  };
  Pixel pixelOf(const Vec3& wWorld) const;
  float pdfW(Pixel p) const;
  // The pixel's radiance spectrum at the group's wavelengths (its colour fitted at load).
  Spectrum radiance(Pixel p, const Wavelengths& lambda) const;
  // A direction toward the light (world space), its pixel, and its density; false if black.
  bool sampleDirection(Vec2 u, Vec3& wWorld, Pixel& pixel) const;

  int width_ = 0, height_ = 0;
  // Each pixel's colour (clamped to >= 0, times scale) fitted once as an unbounded sigmoid
  // spectrum: the fit (rgbToUnbounded, a search of the RGB table) cost more than the lookup.
  std::vector<RgbUnbounded> fitted_;
  glm::mat3 toWorld_{1.0f};
  PiecewiseConstant1D rows_;                  // weight: sum of luminance x (cos theta0 - cos theta1)
  std::vector<PiecewiseConstant1D> columns_;  // per row, weight: luminance
  float luminanceIntegral_ = 0;
  uint64_t droppedPixels_ = 0;
  SceneSphere sphere_;
};

// Loads an OpenEXR lat-long map. On failure returns nullptr and an error naming the file.
std::unique_ptr<ImageEnvironment> loadImageEnvironment(const std::string& path, const Mat4& environmentToWorld,
                                                       float scale, std::string& error);

}  // namespace tex::render
