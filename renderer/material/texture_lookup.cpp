#include "renderer/material/texture_lookup.h"

#include "renderer/image/image_io.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace tex::render {

namespace {

// A texel coordinate held within +-2^30, so that its floor, the conversion to int and the +1 of
// the neighbour stay defined (beyond 2^31 the conversion had given INT_MIN: a clamped texture
// returned its left edge for u * width >= 2^31; an overflow to inf gave NaN). Coordinates that
// large are past a float's texel precision, so only clamping means anything there, and it stays
// exact.
float heldCoordinate(float x) { return std::clamp(x, -1073741824.0f, 1073741824.0f); }

int wrapIndex(int i, int n, WrapMode mode) {
  if (unsigned(i) < unsigned(n)) return i;  // inside the image: every mode keeps it (no division)
  switch (mode) {
    case WrapMode::ClampToEdge:
      return std::clamp(i, 0, n - 1);
    case WrapMode::MirroredRepeat: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case WrapMode::Repeat:
    default: {
      int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

// sRGB decoding by table (4097 points over [0, 1], linear interpolation: within 2e-7 of the
// formula): four texels of three channels per lookup made powf the hottest call of textured
// scenes.
float srgbToLinearFast(float c) {
  static const std::vector<float> table = [] {
    std::vector<float> t(4097);
    for (size_t i = 0; i < t.size(); ++i) t[i] = srgbToLinear(float(i) / 4096.0f);
    return t;
  }();
  if (!(c > 0.0f) || c >= 1.0f) return srgbToLinear(c);
  const float x = c * 4096.0f;
  const int i = int(x);
  const float f = x - float(i);
  return table[size_t(i)] + f * (table[size_t(i) + 1] - table[size_t(i)]);
}

// An 8-bit value decoded, as srgbToLinearFast(byte / 255) or byte / 255: the same floats the
// float path computes from the same values, one load instead of the table interpolation.
struct ByteTables {
  float linear[256], srgb[256];
  ByteTables() {
    for (int b = 0; b < 256; ++b) {
      linear[b] = float(b) / 255.0f;
      srgb[b] = srgbToLinearFast(linear[b]);
    }
  }
};

Vec4 byteTexel(const ImageData& img, size_t index, bool srgb) {
  static const ByteTables tables;
  const uint8_t* px = &img.bytes[index];
  const float* colour = srgb ? tables.srgb : tables.linear;  // alpha is never sRGB encoded
  switch (img.channels) {
    case 1: return Vec4(colour[px[0]], colour[px[0]], colour[px[0]], 1.0f);
    case 2: return Vec4(colour[px[0]], colour[px[0]], colour[px[0]], tables.linear[px[1]]);
    case 3: return Vec4(colour[px[0]], colour[px[1]], colour[px[2]], 1.0f);
    default: return Vec4(colour[px[0]], colour[px[1]], colour[px[2]], tables.linear[px[3]]);
  }
}

Vec4 texel(const ImageData& img, int x, int y, bool srgb) {
  const size_t index = (size_t(y) * size_t(img.width) + size_t(x)) * size_t(img.channels);
  if (!img.bytes.empty()) return byteTexel(img, index, srgb);
  const float* px = &img.pixels[index];
  Vec4 c(1.0f);
  switch (img.channels) {
    case 1: c = Vec4(px[0], px[0], px[0], 1.0f); break;
    case 2: c = Vec4(px[0], px[0], px[0], px[1]); break;
    case 3: c = Vec4(px[0], px[1], px[2], 1.0f); break;
    default: c = Vec4(px[0], px[1], px[2], px[3]); break;
  }
  if (srgb) {
    c.x = srgbToLinearFast(c.x);
    c.y = srgbToLinearFast(c.y);
    c.z = srgbToLinearFast(c.z);
  }
  return c;
}

}  // namespace

bool textureHasImage(const SceneDescription& scene, const TextureRef& ref) {
  if (ref.image < 0 || size_t(ref.image) >= scene.images.size()) return false;
  const ImageData& img = scene.images[size_t(ref.image)];
  return img.width > 0 && img.height > 0 && img.channels > 0 &&
         img.valueCount() >= size_t(img.width) * size_t(img.height) * size_t(img.channels);
}

Vec4 lookupTexture(const SceneDescription& scene, const TextureRef& ref, Vec2 uv0, Vec2 uv1, bool srgb,
                   const Vec4& fallback) {
  if (!textureHasImage(scene, ref)) return fallback;
  const ImageData& img = scene.images[size_t(ref.image)];
  Vec2 uv = ref.texCoord == 1 ? uv1 : uv0;
  // KHR_texture_transform: translation * rotation * scale, rotation counter-clockwise in uv.
  if (ref.rotation != 0.0f || ref.scale != Vec2(1.0f) || ref.offset != Vec2(0.0f)) {
    const Vec2 s = uv * ref.scale;
    const float c = std::cos(ref.rotation), r = std::sin(ref.rotation);
    uv = Vec2(c * s.x + r * s.y, -r * s.x + c * s.y) + ref.offset;
  }
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return fallback;
  const float x = heldCoordinate(uv.x * float(img.width) - 0.5f), y = heldCoordinate(uv.y * float(img.height) - 0.5f);
  if (ref.nearest) {
    const int ix = wrapIndex(int(std::floor(x + 0.5f)), img.width, ref.wrapS);
    const int iy = wrapIndex(int(std::floor(y + 0.5f)), img.height, ref.wrapT);
    return texel(img, ix, iy, srgb);
  }
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  const int ix = int(fx), iy = int(fy);
  const int x0 = wrapIndex(ix, img.width, ref.wrapS), x1 = wrapIndex(ix + 1, img.width, ref.wrapS);
  const int y0 = wrapIndex(iy, img.height, ref.wrapT), y1 = wrapIndex(iy + 1, img.height, ref.wrapT);
  return (texel(img, x0, y0, srgb) * (1 - tx) + texel(img, x1, y0, srgb) * tx) * (1 - ty) +
         (texel(img, x0, y1, srgb) * (1 - tx) + texel(img, x1, y1, srgb) * tx) * ty;
}

}  // namespace tex::render
