// Layout of the RGB-to-spectrum table file that renderer/spectra/generate_rgb_table.cpp writes
// and renderer/spectra/rgb_table.cpp reads (embedded in the library at build time).
#pragma once
#include <cstdint>

namespace tex::render {

struct RgbTableHeader {
  uint32_t magic = 0x53524754;  // "TGRS" little-endian
  uint32_t version = 2;
  uint32_t resolution = 0;
  uint32_t reserved = 0;
};
// Followed by `resolution` floats z (the largest component's value at each slice), `resolution`
// floats x/y (the ratios of the other two components to the largest at each node), both
// increasing from 0 to 1, and 3 * resolution^3 * 3 floats: coefficients (c0, c1, c2) in nm
// units, indexed [largest component l][z][y][x], for the colour
// rgb[l] = z, rgb[(l+1)%3] = x z, rgb[(l+2)%3] = y z.

}  // namespace tex::render
