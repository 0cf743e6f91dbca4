#include "renderer/spectra/rgb_table.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "renderer/spectra/rgb_table_format.h"

// Defined by rgb_table_blob.cpp (assembler labels around the embedded file).
extern "C" const unsigned char texRgbSigmoidTableBlob[];
extern "C" const unsigned char texRgbSigmoidTableBlobEnd[];

namespace tex::render {

namespace {

[[noreturn]] void fail(const char* why) {
  std::fprintf(stderr, "tex: the embedded RGB-to-spectrum table is malformed (%s); rebuild\n", why);
  std::abort();
}

RgbSigmoidTable loadTable() {
  const unsigned char* begin = texRgbSigmoidTableBlob;
  const size_t bytes = size_t(texRgbSigmoidTableBlobEnd - texRgbSigmoidTableBlob);
  RgbTableHeader header;
  if (bytes < sizeof header) fail("too short");
  std::memcpy(&header, begin, sizeof header);
  const RgbTableHeader expected;
  if (header.magic != expected.magic || header.version != expected.version) fail("wrong magic or version");
  const size_t res = header.resolution;
  if (res < 2 || res > 1024) fail("bad resolution");
  if (bytes != sizeof header + sizeof(float) * (2 * res + 9 * res * res * res)) fail("wrong size");
  // The blob is 64-byte aligned and the header is 16 bytes, so the floats are aligned too.
  RgbSigmoidTable table;
  table.resolution = int(res);
  table.zNodes = reinterpret_cast<const float*>(begin + sizeof header);
  table.xyNodes = table.zNodes + res;
  table.coeffs = table.xyNodes + res;
  if (table.zNodes[0] != 0.0f || table.zNodes[res - 1] != 1.0f) fail("z nodes do not span [0,1]");
  if (table.xyNodes[0] != 0.0f || table.xyNodes[res - 1] != 1.0f) fail("x/y nodes do not span [0,1]");
  for (size_t k = 1; k < res; ++k)
    if (!(table.zNodes[k] > table.zNodes[k - 1]) || !(table.xyNodes[k] > table.xyNodes[k - 1]))
      fail("nodes not increasing");
  return table;
}

}  // namespace

const RgbSigmoidTable& rgbSigmoidTable() {
  static const RgbSigmoidTable table = loadTable();
  return table;
}

}  // namespace tex::render
