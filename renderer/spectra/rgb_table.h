// The RGB-to-spectrum coefficient table (Jakob & Hanika 2019), fitted at build time by
// renderer/spectra/generate_rgb_table.cpp and embedded in the library (rgb_table_blob.cpp).
// Layout: renderer/spectra/rgb_table_format.h. Most code wants rgbToSigmoid (rgb_spectrum.h);
// this view is for lookups and tests of the fit itself.
#pragma once
#include <cstddef>

namespace tex::render {

struct RgbSigmoidTable {
  int resolution = 0;
  const float* zNodes = nullptr;   // resolution values, increasing from 0 to 1
  const float* xyNodes = nullptr;  // resolution values, increasing from 0 to 1
  const float* coeffs = nullptr;  // [3][resolution z][resolution y][resolution x][3], nm units

  const float* cell(int largest, int zi, int yi, int xi) const {
    const size_t r = size_t(resolution);
    return coeffs + (((size_t(largest) * r + size_t(zi)) * r + size_t(yi)) * r + size_t(xi)) * 3;
  }
};

// The embedded table, validated on first use (aborts with a message if the blob is malformed,
// which only a broken build can cause).
const RgbSigmoidTable& rgbSigmoidTable();

}  // namespace tex::render
