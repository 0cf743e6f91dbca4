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
  // variance of each pixel estimate): z = (a - b) / sqrt(varA + varB). A grey pixel (R = G = B
  // and equal variances in both images) is tested once, not three times.
  bool zTested = false;
  uint64_t zCount = 0;            // channels tested (with positive variance)
  double zMeanSquare = 0;         // about 1 if the variances are right and the means agree
  double zOutlierFraction = 0;    // fraction with |z| > 3; 0.0027 expected for Gaussian noise
  uint64_t zNonFinite = 0;        // channels with a NaN or infinite value or variance: a failure
  uint64_t zUntestable = 0;       // channels that differ but have no variance in either image
  uint64_t zChannels = 0;         // all channels looked at (after merging grey pixels)
  // Passes when no channel is non-finite, at most 1 % of the differing channels have no
  // variance, at least 30 channels were tested, and the outliers are at most
  // 1 % + 3 sigma of a binomial at 1 % (so that small images are not failed by one pixel).
  bool zPass = false;
  std::string zVerdict;           // why it failed or could not decide ("" when it passed)

  // Whole-image means (A - B per channel), tested by batch means: the image is cut into a grid
  // of blocks (up to 8 x 8, at least 8 pixels a side), and the blocks' mean differences give a
  // t statistic with (blocks - 1) degrees of freedom. A bias spread thinly over many pixels
  // (a few percent everywhere in an object) hides in the per-pixel test's noise but shifts
  // the mean. Needs no variance channels (works on other renderers' images) and is not misled
  // by filtered films' correlated pixels, as blocks are much wider than a filter.
  bool meanTested = false;        // at least 16 blocks and every value finite
  int meanBlocks = 0;
  double meanA[3] = {0, 0, 0}, meanB[3] = {0, 0, 0};
  double meanT[3] = {0, 0, 0};    // t of the block differences' mean; 0 when they are all 0
  // Differ when some |t| > 4.5 (false alarm below about 1.3e-3 an image at 16 blocks, 1e-4 at
  // 64) and the difference is above float rounding (1e-5 of the larger mean).
  bool meanPass = false;
  std::string meanVerdict;        // why it failed or could not decide ("" when it passed)
};

// Compares two images of the same size; error message if they differ in size or lack RGB.
std::string compareImages(const ExrImage& a, const ExrImage& b, ImageComparison& out);

// The comparison as one JSON object (keys: width, height, rmse, rmse_r, rmse_g, rmse_b,
// relative_mse, max_abs_difference, ztest {tested, count, mean_square, outlier_fraction,
// pass} when variance channels exist, and meantest {blocks, mean_a, mean_b, t, pass} when the
// image is large enough).
std::string comparisonToJson(const ImageComparison& c, const std::string& pathA, const std::string& pathB);

}  // namespace tex
