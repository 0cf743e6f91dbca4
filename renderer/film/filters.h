// Reconstruction filters, separable: k(dx, dy) = k1(dx) k1(dy), with dx, dy in pixels from
// the pixel centre. Each 1-D profile is normalised to unit integral, so the filter
// integrates to 1 over the plane (in pixel units).
#pragma once
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace tex {

enum class FilterKind { Box, Tent, Gaussian, Mitchell };

class Filter {
 public:
  // Box: radius 0.5; tent: radius 1; Gaussian: sigma 0.5, radius 1.5, shifted to reach 0 at
  // the radius; Mitchell-Netravali: B = C = 1/3, radius 2 (has negative lobes).
  explicit Filter(FilterKind kind);

  FilterKind kind() const { return kind_; }
  float radiusPixels() const { return radius_; }
  // The normalised 1-D profile at offset dx (pixels). Inline: the film calls it six times a
  // record.
  float evaluate1d(float dx) const {
    if (table_.empty()) return raw(dx) * normalisation_;
    const float t = std::fabs(dx) * (float(kTableSize) / radius_);
    if (!(t < float(kTableSize))) return 0.0f;
    const int i = int(t);
    const float f = t - float(i);
    return table_[size_t(i)] + f * (table_[size_t(i) + 1] - table_[size_t(i)]);
  }
  float evaluate(float dx, float dy) const { return evaluate1d(dx) * evaluate1d(dy); }

 private:
  float raw(float dx) const;
  FilterKind kind_;
  float radius_;
  float normalisation_ = 1;
  // Smooth profiles (Gaussian, Mitchell) are tabulated at kTableSize + 1 points over
  // [0, radius] and interpolated linearly: every record splats up to 16 pixels, and two exp()
  // per axis per pixel cost more than the rest of the film.
  static constexpr int kTableSize = 1024;
  std::vector<float> table_;
};

const char* filterName(FilterKind kind);
std::optional<FilterKind> parseFilterKind(const std::string& name);

}  // namespace tex
