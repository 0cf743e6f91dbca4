// `tex compare`: image differences (RMSE, relative MSE, per-pixel Z-test with variances, a
// batch-means test of the image means).
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "cli/command.h"
#include "renderer/image/compare.h"

namespace tex::cli {

namespace {

const char* kCompareUsage =
    "usage: tex compare A.exr B.exr [--json] [--max-rmse X]\n"
    "\n"
    "Compares two images of the same size (OpenEXR or PNG); B is the reference for the\n"
    "relative MSE. When either has variance.R/G/B channels (tex develop writes them), a\n"
    "per-pixel Z-test says whether the images agree within their estimated noise: it passes when\n"
    "at most 1% (plus 3 binomial sigma) of the tested channels have |z| > 3, none is NaN or\n"
    "infinite, at most 1% differ without a variance in either image, and at least 30 were\n"
    "tested (grey pixels count once). Below about 16 samples per pixel it is unreliable; a note\n"
    "says so when the images' metadata show it.\n"
    "\n"
    "The image means are tested too, by batch means over a grid of up to 8x8 blocks (at least\n"
    "16 blocks of 8x8 pixels): a bias spread thinly over many pixels passes the per-pixel test\n"
    "but moves the mean. The images differ when some channel has |t| > 4.5 (t of the blocks'\n"
    "mean differences). This test needs no variance channels, so it also compares images from\n"
    "other renderers.\n"
    "\n"
    "options:\n"
    "  --json        print one JSON object (keys rmse, rmse_r, rmse_g, rmse_b, relative_mse,\n"
    "                max_abs_difference, ztest{count, mean_square, outlier_fraction, non_finite,\n"
    "                untestable, pass[, verdict]}, meantest{blocks, mean_a, mean_b, t,\n"
    "                pass[, verdict]})\n"
    "  --max-rmse X  exit with status 3 if the RMSE exceeds X\n"
    "\n"
    "exit status: 0 compared, 1 unreadable or mismatched inputs, 2 usage, 3 over --max-rmse\n";

int usage(const std::string& message) {
  std::fprintf(stderr, "tex compare: error: %s\n%s", message.c_str(), kCompareUsage);
  return 2;
}

std::string readAny(const std::string& path, ExrImage& out) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& ch : extension) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  const bool png = extension == ".png";  // any case: C1.PNG was read as OpenEXR
  if (!png) return readExr(path, out);
  RgbImage rgb;
  if (std::string e = readRgbImage(path, rgb); !e.empty()) return e;
  out = ExrImage{};
  out.width = rgb.width, out.height = rgb.height;
  const char* names[3] = {"R", "G", "B"};
  for (int k = 0; k < 3; ++k) {
    ExrChannel c{names[k], std::vector<float>(size_t(rgb.width) * rgb.height)};
    for (size_t p = 0; p < c.values.size(); ++p) c.values[p] = rgb.rgb[p * 3 + k];
    out.channels.push_back(std::move(c));
  }
  return "";
}

}  // namespace

int runCompare(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kCompareUsage, stdout);
    return 0;
  }
  std::vector<std::string> paths;
  bool json = false;
  double maxRmse = -1;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--json") {
      json = true;
    } else if (a == "--max-rmse") {
      if (i + 1 >= args.size()) return usage("--max-rmse needs a number");
      char* end = nullptr;
      const std::string& text = args[++i];
      maxRmse = std::strtod(text.c_str(), &end);
      // An empty value (an unset shell variable) had read as 0, the strictest threshold.
      if (end == text.c_str() || *end != '\0' || !(maxRmse >= 0)) return usage("--max-rmse needs a non-negative number");
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option '" + a + "'");
    } else {
      paths.push_back(a);
    }
  }
  if (paths.size() != 2) return usage("need exactly two images");
  ExrImage a, b;
  for (auto [path, image] : {std::pair{&paths[0], &a}, std::pair{&paths[1], &b}}) {
    if (std::string e = readAny(*path, *image); !e.empty()) {
      std::fprintf(stderr, "tex compare: error: %s\n", e.c_str());
      return 1;
    }
  }
  // Below about 16 samples per pixel pixel values are far from normal (a few bright paths
  // dominate), and the Z-test rejects renders of one scene: say so next to its verdict.
  for (const auto& [path, image] : {std::pair{&paths[0], &a}, std::pair{&paths[1], &b}}) {
    const auto samples = image->metadata.find("tex.samples");
    const double pixels = double(image->width) * image->height;
    if (samples == image->metadata.end() || !(pixels > 0)) continue;
    const double perPixel = std::strtod(samples->second.c_str(), nullptr) / pixels;
    if (perPixel > 0 && perPixel < 16)
      std::fprintf(stderr, "tex compare: note: %s has %.3g samples per pixel; below about 16 the Z-test is unreliable "
                           "(pixel values are far from normally distributed)\n", path->c_str(), perPixel);
  }
  ImageComparison c;
  if (std::string e = compareImages(a, b, c); !e.empty()) {
    std::fprintf(stderr, "tex compare: error: %s and %s: %s\n", paths[0].c_str(), paths[1].c_str(), e.c_str());
    return 1;
  }
  if (json) {
    std::printf("%s\n", comparisonToJson(c, paths[0], paths[1]).c_str());
  } else {
    std::printf("%dx%d  rmse %.6g (R %.6g, G %.6g, B %.6g)  relative mse %.6g  max |a-b| %.6g\n", c.width, c.height,
                c.rmse, c.rmseChannel[0], c.rmseChannel[1], c.rmseChannel[2], c.relativeMse, c.maxAbsDifference);
    if (c.zTested) {
      std::printf("z-test over %llu pixel channels: mean z^2 %.4g, |z| > 3 in %.4g%% (%s)\n",
                  (unsigned long long)c.zCount, c.zMeanSquare, 100.0 * c.zOutlierFraction,
                  c.zPass ? "consistent within noise" : c.zVerdict.c_str());
    } else {
      // Without variance channels, or with only zero variances (1 sample per pixel: no
      // estimate of the noise), there is nothing to test against.
      std::printf("z-test: no variance estimates (no variance channels, or all zero, as at 1 sample per pixel)\n");
    }
    if (c.meanTested) {
      std::printf("image means over %d blocks: R %.6g vs %.6g (t %.3g), G %.6g vs %.6g (t %.3g), B %.6g vs %.6g (t %.3g) (%s)\n",
                  c.meanBlocks, c.meanA[0], c.meanB[0], c.meanT[0], c.meanA[1], c.meanB[1], c.meanT[1], c.meanA[2],
                  c.meanB[2], c.meanT[2], c.meanPass ? "consistent within noise" : "DIFFER");
    } else {
      std::printf("image means: %s\n", c.meanVerdict.c_str());
    }
  }
  if (maxRmse >= 0 && !(c.rmse <= maxRmse)) {  // a NaN rmse (non-finite pixels) fails too
    std::fprintf(stderr, "tex compare: rmse %.6g exceeds --max-rmse %.6g\n", c.rmse, maxRmse);
    return 3;
  }
  return 0;
}

TEX_COMMAND("compare", "compare two images: RMSE, relative MSE, per-pixel Z-test", &runCompare);

}  // namespace tex::cli
