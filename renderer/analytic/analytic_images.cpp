#include "renderer/analytic/analytic_images.h"

#include <algorithm>
#include <cmath>

namespace tex {

namespace {
constexpr double kDiskRadius = 0.3;
constexpr double kCheckerFrequency = 8.37;
constexpr double kGaussianSigma = 0.15;
constexpr double kStepOffset = 0.35, kStepSlope = 0.3;

// Square wave s(t) = +1 on even cells of width 1/f, -1 on odd; its integral from 0 to x.
double squareWaveIntegral(double x) {
  const double t = x * kCheckerFrequency;
  const double cell = std::floor(t);
  const double inCell = t - cell;
  const bool odd = std::fmod(cell, 2.0) != 0.0;
  return (odd ? 1.0 - inCell : inCell) / kCheckerFrequency;  // whole pairs of cells integrate to 0
}

double gaussianIntegral1d(double a, double b) {  // integral of exp(-(t-0.5)^2 / (2 s^2))
  const double k = 1.0 / (std::sqrt(2.0) * kGaussianSigma);
  return kGaussianSigma * std::sqrt(M_PI / 2.0) * (std::erf((b - 0.5) * k) - std::erf((a - 0.5) * k));
}

// Average over [x0,x1] of g(x) by the midpoint rule with many points (g is continuous).
template <class G>
double average1d(double x0, double x1, G&& g) {
  const int steps = 4000;
  double sum = 0;
  for (int i = 0; i < steps; ++i) sum += g(x0 + (x1 - x0) * (i + 0.5) / steps);
  return sum / steps;
}
}  // namespace

float analyticValue(AnalyticImage image, float xf, float yf) {
  const double x = xf, y = yf;
  switch (image) {
    case AnalyticImage::Disk: return (x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) < kDiskRadius * kDiskRadius ? 1.0f : 0.0f;
    case AnalyticImage::Checkerboard: {
      const long cx = long(std::floor(x * kCheckerFrequency)), cy = long(std::floor(y * kCheckerFrequency));
      return ((cx + cy) & 1) == 0 ? 0.0f : 1.0f;
    }
    case AnalyticImage::Gaussian:
      return float(std::exp(-((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5)) / (2 * kGaussianSigma * kGaussianSigma)));
    case AnalyticImage::Step: return x < kStepOffset + kStepSlope * y ? 1.0f : 0.0f;
  }
  return 0.0f;
}

std::vector<double> exactPixelAverages(AnalyticImage image, int width, int height) {
  std::vector<double> out(size_t(width) * height, 0.0);
  for (int py = 0; py < height; ++py) {
    const double y0 = double(py) / height, y1 = double(py + 1) / height;
    for (int px = 0; px < width; ++px) {
      const double x0 = double(px) / width, x1 = double(px + 1) / width;
      double value = 0;
      switch (image) {
        case AnalyticImage::Gaussian:
          value = gaussianIntegral1d(x0, x1) * gaussianIntegral1d(y0, y1) / ((x1 - x0) * (y1 - y0));
          break;
        case AnalyticImage::Checkerboard: {
          // f = (1 - s(x) s(y)) / 2 with s = +-1 on cells: separable averages.
          const double sx = (squareWaveIntegral(x1) - squareWaveIntegral(x0)) / (x1 - x0);
          const double sy = (squareWaveIntegral(y1) - squareWaveIntegral(y0)) / (y1 - y0);
          value = 0.5 * (1.0 - sx * sy);
          break;
        }
        case AnalyticImage::Disk:
          // For each x, the length of the chord inside the disk within [y0, y1].
          value = average1d(x0, x1, [&](double x) {
                    const double d2 = kDiskRadius * kDiskRadius - (x - 0.5) * (x - 0.5);
                    if (d2 <= 0) return 0.0;
                    const double h = std::sqrt(d2);
                    return std::max(0.0, std::min(y1, 0.5 + h) - std::max(y0, 0.5 - h));
                  }) / (y1 - y0);
          break;
        case AnalyticImage::Step:
          // For each y, the length of [x0, x1] left of the edge.
          value = average1d(y0, y1, [&](double y) {
                    return std::clamp(kStepOffset + kStepSlope * y - x0, 0.0, x1 - x0);
                  }) / (x1 - x0);
          break;
      }
      out[size_t(py) * width + px] = value;
    }
  }
  return out;
}

const char* analyticImageName(AnalyticImage image) {
  switch (image) {
    case AnalyticImage::Disk: return "disk";
    case AnalyticImage::Checkerboard: return "checkerboard";
    case AnalyticImage::Gaussian: return "gaussian";
    case AnalyticImage::Step: return "step";
  }
  return "?";
}

std::optional<AnalyticImage> parseAnalyticImage(const std::string& name) {
  for (AnalyticImage image : kAllAnalyticImages) {
    if (name == analyticImageName(image)) return image;
  }
  if (name == "checker") return AnalyticImage::Checkerboard;
  return std::nullopt;
}

}  // namespace tex
