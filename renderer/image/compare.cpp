#include "renderer/image/compare.h"

#include <algorithm>
#include <cmath>
#include <vector>
#include <cstdio>

namespace tex {

namespace {
const char* kRgb[3] = {"R", "G", "B"};

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else out += c;
  }
  return out + "\"";
}

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", x);
  return buffer;
}
// Batch means over a grid of blocks (see ImageComparison::meanTested).
void testBlockMeans(const ExrChannel* const* ca, const ExrChannel* const* cb, int width, int height, ImageComparison& out) {
  constexpr int kMinBlockSide = 8, kMaxBlocksPerAxis = 8, kMinBlocks = 16;
  constexpr double kTLimit = 4.5, kRoundingFloor = 1e-5;
  const int bx = std::min(kMaxBlocksPerAxis, width / kMinBlockSide), by = std::min(kMaxBlocksPerAxis, height / kMinBlockSide);
  if (bx * by < kMinBlocks) {
    out.meanVerdict = "cannot decide: the image is too small for " + std::to_string(kMinBlocks) + " blocks of " +
                      std::to_string(kMinBlockSide) + "x" + std::to_string(kMinBlockSide) + " pixels";
    return;
  }
  out.meanBlocks = bx * by;
  std::string failed;
  for (int k = 0; k < 3; ++k) {
    double sumDiff = 0, sumDiffSquares = 0, sumA = 0, sumB = 0;
    for (int j = 0; j < by; ++j)
      for (int i = 0; i < bx; ++i) {
        const int x0 = int(int64_t(i) * width / bx), x1 = int(int64_t(i + 1) * width / bx);
        const int y0 = int(int64_t(j) * height / by), y1 = int(int64_t(j + 1) * height / by);
        double blockA = 0, blockB = 0;
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            const size_t p = size_t(y) * size_t(width) + size_t(x);
            blockA += ca[k]->values[p];
            blockB += cb[k]->values[p];
          }
        const double count = double(x1 - x0) * double(y1 - y0);
        if (!std::isfinite(blockA) || !std::isfinite(blockB)) {
          out.meanVerdict = std::string("cannot decide: ") + kRgb[k] + " has NaN or infinite values";
          return;
        }
        const double diff = (blockA - blockB) / count;
        sumA += blockA, sumB += blockB;
        sumDiff += diff, sumDiffSquares += diff * diff;
      }
    const double blocks = double(out.meanBlocks), pixels = double(width) * double(height);
    out.meanA[k] = sumA / pixels, out.meanB[k] = sumB / pixels;
    const double mean = sumDiff / blocks;
    const double variance = std::max(0.0, (sumDiffSquares - blocks * mean * mean) / (blocks - 1.0));
    const double standardError = std::sqrt(variance / blocks);
    out.meanT[k] = mean == 0.0 ? 0.0 : standardError > 0.0 ? mean / standardError : std::copysign(HUGE_VAL, mean);
    const double scale = std::max(std::fabs(out.meanA[k]), std::fabs(out.meanB[k]));
    if (std::fabs(out.meanT[k]) > kTLimit && std::fabs(out.meanA[k] - out.meanB[k]) > kRoundingFloor * scale) {
      char buffer[96];
      std::snprintf(buffer, sizeof buffer, "%s%s %.6g vs %.6g (t %.3g)", failed.empty() ? "" : ", ", kRgb[k],
                    out.meanA[k], out.meanB[k], out.meanT[k]);
      failed += buffer;
    }
  }
  out.meanTested = true;
  if (!failed.empty()) out.meanVerdict = "image means differ: " + failed;
  out.meanPass = failed.empty();
}

}  // namespace

std::string compareImages(const ExrImage& a, const ExrImage& b, ImageComparison& out) {
  out = ImageComparison{};
  if (a.width != b.width || a.height != b.height) {
    return "images differ in size: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " vs " +
           std::to_string(b.width) + "x" + std::to_string(b.height);
  }
  const ExrChannel* ca[3];
  const ExrChannel* cb[3];
  const ExrChannel* va[3];
  const ExrChannel* vb[3];
  for (int k = 0; k < 3; ++k) {
    ca[k] = a.find(kRgb[k]);
    cb[k] = b.find(kRgb[k]);
    if (ca[k] == nullptr) ca[k] = a.find("Y");
    if (cb[k] == nullptr) cb[k] = b.find("Y");
    if (ca[k] == nullptr || cb[k] == nullptr) return std::string("image without channel ") + kRgb[k];
    va[k] = a.find(std::string("variance.") + kRgb[k]);
    vb[k] = b.find(std::string("variance.") + kRgb[k]);
  }
  out.width = a.width;
  out.height = a.height;
  const size_t pixels = size_t(a.width) * a.height;
  double sum = 0, relative = 0, zSquares = 0;
  uint64_t outliers = 0;
  const bool anyVariance = va[0] || va[1] || va[2] || vb[0] || vb[1] || vb[2];
  const auto varianceOf = [&](const ExrChannel* const* v, int k, size_t p) { return v[k] ? double(v[k]->values[p]) : 0.0; };
  // Grey pixels (the three channels equal in value and variance in both images), found once.
  std::vector<uint8_t> grey(anyVariance ? pixels : 0, 1);
  for (size_t p = 0; p < grey.size(); ++p)
    for (int k = 1; k < 3; ++k)
      if (ca[k]->values[p] != ca[0]->values[p] || cb[k]->values[p] != cb[0]->values[p] ||
          varianceOf(va, k, p) != varianceOf(va, 0, p) || varianceOf(vb, k, p) != varianceOf(vb, 0, p))
        grey[p] = 0;
  for (int k = 0; k < 3; ++k) {
    double channelSum = 0;
    for (size_t p = 0; p < pixels; ++p) {
      const double x = ca[k]->values[p], y = cb[k]->values[p];
      const double d = x - y;
      channelSum += d * d;
      relative += d * d / (y * y + 0.01);
      if (std::fabs(d) > out.maxAbsDifference || std::isnan(d)) out.maxAbsDifference = std::fabs(d);
      if (!anyVariance || (k > 0 && grey[p])) continue;
      ++out.zChannels;
      const double variance = varianceOf(va, k, p) + varianceOf(vb, k, p);
      if (!std::isfinite(d) || !std::isfinite(variance)) {
        ++out.zNonFinite;  // a NaN had passed as z = NaN, never an outlier
      } else if (variance > 0) {
        const double z = d / std::sqrt(variance);
        zSquares += z * z;
        outliers += std::fabs(z) > 3.0;
        out.zCount++;
      } else if (d != 0.0) {
        ++out.zUntestable;  // no noise estimate in either image, yet they differ
      }
    }
    out.rmseChannel[k] = pixels > 0 ? std::sqrt(channelSum / pixels) : 0.0;
    sum += channelSum;
  }
  const double n = double(pixels) * 3;
  out.rmse = n > 0 ? std::sqrt(sum / n) : 0.0;
  out.relativeMse = n > 0 ? relative / n : 0.0;
  out.zTested = out.zCount > 0 || out.zNonFinite > 0;
  if (out.zTested) {
    out.zMeanSquare = out.zCount > 0 ? zSquares / double(out.zCount) : 0.0;
    out.zOutlierFraction = out.zCount > 0 ? double(outliers) / double(out.zCount) : 0.0;
    const double tested = double(out.zCount);
    const double allowedOutliers = 0.01 * tested + 3.0 * std::sqrt(0.01 * 0.99 * tested);
    if (out.zNonFinite > 0) {
      out.zVerdict = std::to_string(out.zNonFinite) + " pixel channels are NaN or infinite";
    } else if (double(out.zUntestable) > 0.01 * double(out.zChannels)) {
      out.zVerdict = "cannot decide: " + std::to_string(out.zUntestable) +
                     " pixel channels differ without a variance in either image (single-sample pixels?)";
    } else if (out.zCount < 30) {
      out.zVerdict = "cannot decide: only " + std::to_string(out.zCount) + " pixel channels have a variance";
    } else if (double(outliers) > allowedOutliers) {
      out.zVerdict = "NOT consistent within noise";
    }
    out.zPass = out.zVerdict.empty();
  }
  testBlockMeans(ca, cb, a.width, a.height, out);
  return "";
}

std::string comparisonToJson(const ImageComparison& c, const std::string& pathA, const std::string& pathB) {
  std::string j = "{\"a\": " + jsonString(pathA) + ", \"b\": " + jsonString(pathB) +
                  ", \"width\": " + std::to_string(c.width) + ", \"height\": " + std::to_string(c.height) +
                  ", \"rmse\": " + jsonNumber(c.rmse) + ", \"rmse_r\": " + jsonNumber(c.rmseChannel[0]) +
                  ", \"rmse_g\": " + jsonNumber(c.rmseChannel[1]) + ", \"rmse_b\": " + jsonNumber(c.rmseChannel[2]) +
                  ", \"relative_mse\": " + jsonNumber(c.relativeMse) +
                  ", \"max_abs_difference\": " + jsonNumber(c.maxAbsDifference);
  if (c.zTested) {
    j += ", \"ztest\": {\"count\": " + std::to_string(c.zCount) + ", \"mean_square\": " + jsonNumber(c.zMeanSquare) +
         ", \"outlier_fraction\": " + jsonNumber(c.zOutlierFraction) + ", \"non_finite\": " + std::to_string(c.zNonFinite) +
         ", \"untestable\": " + std::to_string(c.zUntestable) + ", \"pass\": " + (c.zPass ? "true" : "false") +
         (c.zPass ? std::string() : ", \"verdict\": " + jsonString(c.zVerdict)) + "}";
  }
  if (c.meanTested) {
    const auto triple = [](const double* v) {
      std::string list(1, '[');
      for (int k = 0; k < 3; ++k) list += (k ? ", " : "") + jsonNumber(v[k]);
      return list + "]";
    };
    j += ", \"meantest\": {\"blocks\": " + std::to_string(c.meanBlocks) + ", \"mean_a\": " + triple(c.meanA) +
         ", \"mean_b\": " + triple(c.meanB) + ", \"t\": " + triple(c.meanT) + ", \"pass\": " + (c.meanPass ? "true" : "false") +
         (c.meanPass ? std::string() : ", \"verdict\": " + jsonString(c.meanVerdict)) + "}";
  }
  return j + "}";
}

}  // namespace tex
