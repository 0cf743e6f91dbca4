// Image lookups shared by the interpreter and the JIT's runtime functions: one C++
// implementation, so both give the same bits.
#include <algorithm>
#include <cmath>

#include "lang/image_table.h"

namespace tex::lang {

namespace {

// A texel index wrapped into [0, n).
int64_t wrapIndex(int64_t i, int64_t n, int32_t wrap) {
  if (wrap == int32_t(ImageWrap::Clamp)) return std::clamp<int64_t>(i, 0, n - 1);
  if (wrap == int32_t(ImageWrap::Mirror)) {
    int64_t m = ((i % (2 * n)) + 2 * n) % (2 * n);
    return m < n ? m : 2 * n - 1 - m;
  }
  return ((i % n) + n) % n;
}

// floor(x) as an integer; |x| beyond 2^40 texels is clamped (such coordinates carry no
// sub-texel precision anyway).
int64_t floorIndex(float x) { return int64_t(std::clamp(std::floor(double(x)), -1099511627776.0, 1099511627776.0)); }

void texel(const ImageLevel& l, int64_t x, int64_t y, int32_t wrap, float out[4]) {
  int64_t wx = wrapIndex(x, l.width, wrap), wy = wrapIndex(y, l.height, wrap);
  l.texel(size_t(wy) * size_t(l.width) + size_t(wx), out);
}

void nearest(const ImageLevel& l, int32_t wrap, float u, float v, float out[4]) {
  texel(l, floorIndex(u * float(l.width)), floorIndex(v * float(l.height)), wrap, out);
}

// Texel centres sit at half-integer positions: (i + 0.5) / width.
void bilinear(const ImageLevel& l, int32_t wrap, float u, float v, float out[4]) {
  float x = u * float(l.width) - 0.5f, y = v * float(l.height) - 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  float tx = x - fx, ty = y - fy;
  int64_t ix = floorIndex(x), iy = floorIndex(y);
  float a[4], b[4], c[4], d[4];
  texel(l, ix, iy, wrap, a);
  texel(l, ix + 1, iy, wrap, b);
  texel(l, ix, iy + 1, wrap, c);
  texel(l, ix + 1, iy + 1, wrap, d);
  for (int k = 0; k < 4; ++k) {
    float top = a[k] + (b[k] - a[k]) * tx;
    float bottom = c[k] + (d[k] - c[k]) * tx;
    out[k] = top + (bottom - top) * ty;
  }
}

}  // namespace

void lookupImage(const LoadedImage& image, ImageFilter filter, int32_t wrap, float u, float v, float dudx, float dvdx,
                 float dudy, float dvdy, float out[4]) {
  std::fill(out, out + 4, 0.0f);
  if (image.levels.empty() || !std::isfinite(u) || !std::isfinite(v)) return;
  const ImageLevel& base = image.levels[0];
  if (filter == ImageFilter::Nearest) return nearest(base, wrap, u, v, out);
  if (filter == ImageFilter::Bilinear) return bilinear(base, wrap, u, v, out);
  float ax = dudx * float(base.width), ay = dvdx * float(base.height);
  float bx = dudy * float(base.width), by = dvdy * float(base.height);
  // NaN derivatives act as zero (docs/language.md), whichever axis they are on: std::max(NaN,
  // y) is NaN, which had discarded the other axis's footprint.
  const float rhoX = std::sqrt(ax * ax + ay * ay), rhoY = std::sqrt(bx * bx + by * by);
  float rho = std::max(rhoX == rhoX ? rhoX : 0.0f, rhoY == rhoY ? rhoY : 0.0f);
  int last = int(image.levels.size()) - 1;
  if (!(rho > 1.0f)) return bilinear(base, wrap, u, v, out);  // magnified, or NaN derivatives
  float lod = std::log2(rho);
  if (!(lod < float(last))) return bilinear(image.levels[size_t(last)], wrap, u, v, out);
  int l0 = int(std::floor(lod));
  float t = lod - float(l0);
  float fine[4], coarse[4];
  bilinear(image.levels[size_t(l0)], wrap, u, v, fine);
  bilinear(image.levels[size_t(l0) + 1], wrap, u, v, coarse);
  for (int k = 0; k < 4; ++k) out[k] = fine[k] + (coarse[k] - fine[k]) * t;
}

void imageLookup(int32_t handle, ImageFilter filter, int32_t wrap, float u, float v, float dudx, float dvdx, float dudy,
                 float dvdy, float out[4]) {
  const LoadedImage* image = ImageTable::global().get(handle);
  if (!image) {
    std::fill(out, out + 4, 0.0f);
    return;
  }
  lookupImage(*image, filter, wrap, u, v, dudx, dvdx, dudy, dvdy, out);
}

void imageSize(int32_t handle, float out[2]) {
  const LoadedImage* image = ImageTable::global().get(handle);
  out[0] = image ? float(image->levels[0].width) : 0.0f;
  out[1] = image ? float(image->levels[0].height) : 0.0f;
}

}  // namespace tex::lang
