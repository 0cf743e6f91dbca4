// Known 2-D images on the film [0,1)^2 with exact pixel averages: the integrands that prove
// the runtime, samplers and film converge at the expected rates.
//   disk:         1 inside the circle of radius 0.3 about (0.5, 0.5), else 0 (curved edge)
//   checkerboard: 8.37 squares per unit, not aligned with pixels (straight axis-aligned edges)
//   gaussian:     exp(-|p - (0.5, 0.5)|^2 / (2 * 0.15^2)) (smooth)
//   step:         1 where x < 0.35 + 0.3 y, else 0 (a slanted straight edge)
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace tex {

enum class AnalyticImage { Disk, Checkerboard, Gaussian, Step };

float analyticValue(AnalyticImage image, float x, float y);

// The exact box-filtered image: the average of the function over each pixel, row-major, top
// row first (closed forms for gaussian and checkerboard; converged 1-D quadrature of exact
// chord lengths for disk and step).
std::vector<double> exactPixelAverages(AnalyticImage image, int width, int height);

const char* analyticImageName(AnalyticImage image);
std::optional<AnalyticImage> parseAnalyticImage(const std::string& name);
inline constexpr AnalyticImage kAllAnalyticImages[] = {AnalyticImage::Disk, AnalyticImage::Checkerboard,
                                                       AnalyticImage::Gaussian, AnalyticImage::Step};

}  // namespace tex
