#include "renderer/film/filters.h"

#include <cmath>

namespace tex {

namespace {
constexpr float kGaussianSigma = 0.5f;

float mitchell1d(float x) {
  constexpr float B = 1.0f / 3.0f, C = 1.0f / 3.0f;
  x = std::fabs(x);  // the classic kernel on [-2, 2]
  if (x < 1.0f) {
    return ((12 - 9 * B - 6 * C) * x * x * x + (-18 + 12 * B + 6 * C) * x * x + (6 - 2 * B)) / 6.0f;
  }
  if (x < 2.0f) {
    return ((-B - 6 * C) * x * x * x + (6 * B + 30 * C) * x * x + (-12 * B - 48 * C) * x + (8 * B + 24 * C)) / 6.0f;
  }
  return 0.0f;
}
}  // namespace

Filter::Filter(FilterKind kind) : kind_(kind) {
  switch (kind) {
    case FilterKind::Box: radius_ = 0.5f; break;
    case FilterKind::Tent: radius_ = 1.0f; break;
    case FilterKind::Gaussian: radius_ = 1.5f; break;
    case FilterKind::Mitchell: radius_ = 2.0f; break;
  }
  // Normalise numerically (midpoint rule, fine enough for these smooth profiles).
  const int steps = 20000;
  double integral = 0;
  for (int i = 0; i < steps; ++i) {
    const float x = -radius_ + (float(i) + 0.5f) * (2 * radius_ / steps);
    integral += raw(x);
  }
  integral *= 2 * radius_ / steps;
  normalisation_ = float(1.0 / integral);
  if (kind_ == FilterKind::Gaussian || kind_ == FilterKind::Mitchell) {
    table_.resize(kTableSize + 1);
    for (int i = 0; i <= kTableSize; ++i) table_[size_t(i)] = raw(radius_ * float(i) / kTableSize) * normalisation_;
  }
}

float Filter::raw(float dx) const {
  const float x = std::fabs(dx);
  if (x > radius_) return 0.0f;
  switch (kind_) {
    case FilterKind::Box: return 1.0f;
    case FilterKind::Tent: return 1.0f - x;
    case FilterKind::Gaussian: {
      const auto g = [](float t) { return std::exp(-t * t / (2 * kGaussianSigma * kGaussianSigma)); };
      return std::max(0.0f, g(x) - g(radius_));
    }
    case FilterKind::Mitchell: return mitchell1d(x);
  }
  return 0.0f;
}

const char* filterName(FilterKind kind) {
  switch (kind) {
    case FilterKind::Box: return "box";
    case FilterKind::Tent: return "tent";
    case FilterKind::Gaussian: return "gaussian";
    case FilterKind::Mitchell: return "mitchell";
  }
  return "?";
}

std::optional<FilterKind> parseFilterKind(const std::string& name) {
  for (FilterKind k : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell}) {
    if (name == filterName(k)) return k;
  }
  return std::nullopt;
}

}  // namespace tex
