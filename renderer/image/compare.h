// Image comparison: RMSE, relative MSE and, when variance channels exist, a per-pixel Z-test
// (are the two images equal within their estimated noise?).
#pragma once
#include <cstdint>
#include <string>

#include "renderer/image/image_io.h"

namespace tex {

struct ImageComparison {
  int width = 0, height = 0;
  double rmse = 0;          // sqrt(mean over pixels and R, G, B of (a - b)^2)
  double rmseChannel[3] = {0, 0, 0};
  double relativeMse = 0;   // mean of (a - b)^2 / (b^2 + 0.01): B is the reference
  double maxAbsDifference = 0;
  // Z-test over pixel channels with a variance in A or B (variance.R/G/B channels, the
  // variance of each pixel estimate): z = (a - b) / sqrt(varA + varB).
  bool zTested = false;
  uint64_t zCount = 0;            // channels tested (with positive variance)
  double zMeanSquare = 0;         // about 1 if the variances are right and the means agree
  double zOutlierFraction = 0;    // fraction with |z| > 3; 0.0027 expected for Gaussian noise
  bool zPass = false;             // zOutlierFraction <= 0.01
};

// Compares two images of the same size; error message if they differ in size or lack RGB.
std::string compareImages(const ExrImage& a, const ExrImage& b, ImageComparison& out);

// The comparison as one JSON object (keys: width, height, rmse, rmse_r, rmse_g, rmse_b,
// relative_mse, max_abs_difference, and ztest {tested, count, mean_square, outlier_fraction,
// pass} when variance channels exist).
std::string comparisonToJson(const ImageComparison& c, const std::string& pathA, const std::string& pathB);

}  // namespace tex
