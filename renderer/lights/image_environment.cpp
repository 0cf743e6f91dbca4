#include "renderer/lights/image_environment.h"

#include <atomic>

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "renderer/core/warp.h"
#include "renderer/lights/constant_environment.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

namespace {

// Y of linear sRGB (Rec. 709 primaries, D65): an illuminant rgb (1,1,1) has Y = 1.
float luminanceOf(const Vec3& rgb) { return 0.2126729f * rgb.x + 0.7151522f * rgb.y + 0.0721750f * rgb.z; }

float rowCosTheta(int row, int height) { return std::cos(kPi * float(row) / float(height)); }

// The orthogonal factor Q of the polar decomposition M = Q P of the matrix's 3x3 part (the
// rotation, or rotation and mirror, nearest to it): the sky's directions go out through Q and
// come back through its transpose, which is its inverse only when Q is orthogonal (normalising
// the columns of a shearing matrix was not). Newton's iteration Q <- (Q + Q^-T) / 2 converges
// quadratically. A rotation times a scale (a TRS transform) is its normalised columns, taken as
// they are. A singular matrix keeps the identity.
glm::mat3 orientationOf(const Mat4& m) {
  glm::mat3 normalised;
  for (int c = 0; c < 3; ++c) {
    const Vec3 axis(m[c]);
    const float len = std::sqrt(lengthSquared(axis));
    normalised[c] = len > 0.0f ? axis / len : Vec3(c == 0, c == 1, c == 2);
  }
  float shear = 0.0f;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) shear = std::max(shear, std::fabs(glm::dot(normalised[a], normalised[b])));
  if (shear < 1e-6f) return normalised;
  glm::dmat3 q(normalised);
  if (!(std::fabs(glm::determinant(q)) > 1e-9)) return glm::mat3(1.0f);
  for (int i = 0; i < 30; ++i) {
    const glm::dmat3 next = 0.5 * (q + glm::transpose(glm::inverse(q)));
    double change = 0.0;
    for (int c = 0; c < 3; ++c) change = std::max(change, glm::length(next[c] - q[c]));
    q = next;
    if (change < 1e-12) break;
  }
  return glm::mat3(q);
}

}  // namespace

ImageEnvironment::ImageEnvironment(const RgbImage& image, const Mat4& environmentToWorld, float scale)
    : width_(image.width), height_(image.height) {
  toWorld_ = orientationOf(environmentToWorld);
  const bool valid = width_ > 0 && height_ > 0 && image.rgb.size() >= size_t(width_) * size_t(height_) * 3;
  if (!valid) width_ = height_ = 1;  // an inconsistent image: one black pixel (the loader reports bad files)
  const size_t pixels = size_t(width_) * size_t(height_);
  fitted_.resize(pixels);
  std::vector<float> luminance(pixels);
  // Each pixel on its own: the result does not depend on the thread count.
  std::atomic<uint64_t> dropped{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, pixels, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      Vec3 c;
      bool broken = false;
      for (int k = 0; k < 3; ++k) {
        const float v = valid ? image.rgb[i * 3 + k] * scale : 0.0f;
        broken = broken || !std::isfinite(v) || v < 0.0f;
        c[k] = v;
      }
      // A pixel with a NaN, infinite or negative channel emits nothing at all (its other
      // channels are as suspect as the broken one).
      if (broken) {
        dropped.fetch_add(1, std::memory_order_relaxed);
        c = Vec3(0.0f);
      }
      fitted_[i] = rgbToUnbounded(c);
      luminance[i] = std::max(0.0f, luminanceOf(c));
    }
  });
  std::vector<float> rowWeights(size_t(height_), 0.0f);
  columns_.reserve(size_t(height_));
  for (int y = 0; y < height_; ++y) {
    std::vector<float> row(luminance.begin() + ptrdiff_t(y) * width_, luminance.begin() + ptrdiff_t(y + 1) * width_);
    columns_.emplace_back(row);
    const float dCos = rowCosTheta(y, height_) - rowCosTheta(y + 1, height_);
    rowWeights[size_t(y)] = float(columns_.back().total()) * dCos;
  }
  rows_ = PiecewiseConstant1D(rowWeights);
  droppedPixels_ = dropped.load();
  // Each pixel spans (2 pi / width) in phi.
  luminanceIntegral_ = float(rows_.total() * 2.0 * double(kPi) / double(std::max(width_, 1)));
}

ImageEnvironment::Pixel ImageEnvironment::pixelOf(const Vec3& wWorld) const {
  const Vec2 uv = directionToSphericalYUp(glm::transpose(toWorld_) * wWorld);
  return {std::clamp(int(uv.x * float(width_)), 0, width_ - 1), std::clamp(int(uv.y * float(height_)), 0, height_ - 1)};
}

float ImageEnvironment::pdfW(Pixel p) const {
  // The column's own weight: the luminance sampleDirection chose by (a load it has just made
  // when this follows a sample; a second array of luminances had cost a cache miss per light
  // sample), and 0 for a pixel whose luminance overflowed, as the sampler treats it.
  return luminanceIntegral_ > 0.0f ? columns_[size_t(p.y)].weight(p.x) / luminanceIntegral_ : 0.0f;
}

Spectrum ImageEnvironment::radiance(Pixel p, const Wavelengths& lambda) const {
  // Bit for bit rgbIlluminantSpectrum(colour, lambda) (rgb_spectrum.h).
  return illuminantSpectrum(fitted_[size_t(p.y) * size_t(width_) + size_t(p.x)], lambda);
}

bool ImageEnvironment::sampleDirection(Vec2 u, Vec3& wWorld, Pixel& pixel) const {
  if (!(luminanceIntegral_ > 0.0f)) return false;
  const PiecewiseConstant1D::Sample row = rows_.sample(u.y);
  const PiecewiseConstant1D::Sample column = columns_[size_t(row.index)].sample(u.x);
  pixel = {column.index, row.index};
  // Uniform in solid angle inside the pixel: cos(theta) and phi uniform over its extent.
  const float cos0 = rowCosTheta(row.index, height_), cos1 = rowCosTheta(row.index + 1, height_);
  const float cosTheta = std::clamp(cos0 + (cos1 - cos0) * row.residual, -1.0f, 1.0f);
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float phi = 2.0f * kPi * (float(column.index) + column.residual) / float(width_);
  const Vec3 local(sinTheta * std::sin(phi), cosTheta, -sinTheta * std::cos(phi));  // as sphericalDirectionYUp
  wWorld = glm::normalize(toWorld_ * local);
  return pdfW(pixel) > 0.0f;
}

float ImageEnvironment::power() const { return kPi * sphere_.radius * sphere_.radius * luminanceIntegral_; }

std::optional<LightLiSample> ImageEnvironment::sampleLi(const Vec3& refPoint, Vec2 u, const Wavelengths& lambda) const {
  LightLiSample s;
  Pixel pixel;
  if (!sampleDirection(u, s.wi, pixel)) return std::nullopt;
  s.pLight = refPoint + s.wi * (2.0f * sphere_.radius);
  s.distance = kInfinity;
  s.L = radiance(pixel, lambda);
  s.pdfW = pdfW(pixel);  // the sampled pixel's density (pdfLi looks the same pixel up)
  return s;
}

float ImageEnvironment::pdfLi(const Vec3& refPoint, const Vec3& wi, const EmitterPoint* onLight) const {
  (void)refPoint;
  (void)onLight;
  return pdfW(pixelOf(wi));
}

std::optional<LightLeSample> ImageEnvironment::sampleLe(Vec2 uPos, Vec2 uDir, const Wavelengths& lambda) const {
  Vec3 wToLight;
  Pixel pixel;
  if (!sampleDirection(uDir, wToLight, pixel)) return std::nullopt;
  LightLeSample s;
  s.ray = environmentEmittedRay(sphere_, wToLight, uPos);
  s.nLight = -wToLight;
  s.L = radiance(pixel, lambda);
  s.pdfPosA = environmentDiskPdfA(sphere_);
  s.pdfDirW = pdfW(pixel);
  return s;
}

void ImageEnvironment::pdfLe(const Ray& ray, const Vec3& nLight, float& pdfPosA, float& pdfDirW) const {
  (void)nLight;
  pdfPosA = environmentDiskPdfA(sphere_);
  pdfDirW = pdfW(pixelOf(-ray.direction));
}

Spectrum ImageEnvironment::Le(const Ray& ray, const Wavelengths& lambda) const {
  return radiance(pixelOf(ray.direction), lambda);
}

std::unique_ptr<ImageEnvironment> loadImageEnvironment(const std::string& path, const Mat4& environmentToWorld,
                                                       float scale, std::string& error) {
  RgbImage image;
  error = readRgbImage(path, image);
  if (error.empty() && (image.width <= 0 || image.height <= 0))
    error = path + ": environment map has no pixels";
  if (!error.empty()) {
    if (error.find(path) == std::string::npos) error = path + ": " + error;
    error = "environment map: " + error;
    return nullptr;
  }
  return std::make_unique<ImageEnvironment>(image, environmentToWorld, scale);
}

}  // namespace tex::render
