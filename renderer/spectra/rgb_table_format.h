// Layout of the RGB-to-spectrum table file that renderer/spectra/generate_rgb_table.cpp writes
// and renderer/spectra/rgb_table.cpp reads (embedded in the library at build time).
#pragma once
#include <cstdint>

namespace tex::render {

struct RgbTableHeader {
  uint32_t magic = 0x53524754;  // "TGRS" little-endian
  uint32_t version = 1;
  uint32_t resolution = 0;
  uint32_t reserved = 0;
};
// Followed by `resolution` floats (the largest component's value at each z slice, increasing
// from 0 to 1) and 3 * resolution^3 * 3 floats: coefficients (c0, c1, c2) in nm units, indexed
// [largest component][z][y][x], where for largest component l the colour is
// rgb[l] = z, rgb[(l+1)%3] = x z, rgb[(l+2)%3] = y z, x and y uniform on [0,1].

}  // namespace tex::render
