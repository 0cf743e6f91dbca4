// Image texture lookups (renderer/material/texture_lookup.h): what a lookup means (texel
// centres, bilinear weights, sRGB decoding before filtering with alpha left linear, wrap modes),
// and that an 8-bit image kept as bytes looks up exactly the floats the same image stored as
// floats gives, for every channel count, filter, wrap mode and decoding.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/image/image_io.h"
#include "renderer/material/texture_lookup.h"
#include "renderer/sampling/pcg.h"

namespace tex::render {
namespace {

SceneDescription sceneWith(ImageData image) {
  SceneDescription scene;
  scene.images.push_back(std::move(image));
  return scene;
}

ImageData byteImage(int width, int height, int channels, std::vector<uint8_t> bytes) {
  ImageData img;
  img.width = width;
  img.height = height;
  img.channels = channels;
  img.bytes = std::move(bytes);
  return img;
}

ImageData asFloats(const ImageData& bytesImage) {
  ImageData img = bytesImage;
  img.bytes.clear();
  for (uint8_t b : bytesImage.bytes) img.pixels.push_back(float(b) / 255.0f);
  return img;
}

TEST(TextureLookup, TexelCentresBilinearWeightsAndSrgbBeforeFiltering) {
  // Two texels side by side: black and 8-bit 128 (sRGB encoded), alpha 0 and 255.
  const SceneDescription scene = sceneWith(byteImage(2, 1, 2, {0, 0, 128, 255}));
  TextureRef ref;
  ref.image = 0;
  ref.wrapS = ref.wrapT = WrapMode::ClampToEdge;
  const float grey = srgbToLinear(128.0f / 255.0f);
  // The second texel's centre is u = 0.75.
  const Vec4 centre = lookupTexture(scene, ref, Vec2(0.75f, 0.5f), Vec2(0.0f), true);
  EXPECT_NEAR(centre.x, grey, 1e-6f);
  EXPECT_NEAR(centre.w, 1.0f, 1e-6f);
  // Halfway between the centres: the mean of the decoded values (decode, then filter), and
  // alpha linear.
  const Vec4 mid = lookupTexture(scene, ref, Vec2(0.5f, 0.5f), Vec2(0.0f), true);
  EXPECT_NEAR(mid.x, 0.5f * grey, 1e-6f);
  EXPECT_NEAR(mid.y, 0.5f * grey, 1e-6f);
  EXPECT_NEAR(mid.w, 0.5f, 1e-6f);
  const Vec4 linear = lookupTexture(scene, ref, Vec2(0.5f, 0.5f), Vec2(0.0f), false);
  EXPECT_NEAR(linear.x, 0.5f * 128.0f / 255.0f, 1e-6f);
  // Repeat wraps u = 1.25 onto 0.25 (the first texel's centre); clamp keeps the edge texel.
  ref.wrapS = WrapMode::Repeat;
  EXPECT_NEAR(lookupTexture(scene, ref, Vec2(1.25f, 0.5f), Vec2(0.0f), true).x, 0.0f, 1e-6f);
  ref.wrapS = WrapMode::ClampToEdge;
  EXPECT_NEAR(lookupTexture(scene, ref, Vec2(1.25f, 0.5f), Vec2(0.0f), true).x, grey, 1e-6f);
  // Far beyond the image, clamping still keeps the edge texel on its side (past u * width =
  // 2^31 the index conversion had overflowed to the left edge), filtered or nearest.
  for (const bool nearest : {false, true}) {
    ref.nearest = nearest;
    for (const float u : {6e5f, 1e6f, 1e12f, 3e38f}) {
      EXPECT_NEAR(lookupTexture(scene, ref, Vec2(u, 0.5f), Vec2(0.0f), true).x, grey, 1e-6f) << u;
      EXPECT_NEAR(lookupTexture(scene, ref, Vec2(-u, 0.5f), Vec2(0.0f), true).x, 0.0f, 1e-6f) << u;
    }
  }
  ref.nearest = false;
  // No image: the fallback.
  TextureRef none;
  EXPECT_EQ(lookupTexture(scene, none, Vec2(0.5f), Vec2(0.0f), true, Vec4(7.0f)), Vec4(7.0f));
}

TEST(TextureLookup, ByteImagesLookUpTheFloatImagesBitsExactly) {
  sampling::Pcg32 rng(3, 11);
  int compared = 0;
  for (int channels = 1; channels <= 4; ++channels) {
    const int width = 7, height = 5;
    std::vector<uint8_t> bytes(size_t(width * height * channels));
    for (uint8_t& b : bytes) b = uint8_t(rng.nextBits() & 0xFF);
    bytes[0] = 0;
    bytes[1 % bytes.size()] = 255;  // both ends of the range (decoded by formula, not table)
    const SceneDescription byteScene = sceneWith(byteImage(width, height, channels, bytes));
    const SceneDescription floatScene = sceneWith(asFloats(byteScene.images[0]));
    for (WrapMode wrap : {WrapMode::Repeat, WrapMode::ClampToEdge, WrapMode::MirroredRepeat}) {
      for (bool nearest : {false, true}) {
        for (bool srgb : {false, true}) {
          TextureRef ref;
          ref.image = 0;
          ref.wrapS = ref.wrapT = wrap;
          ref.nearest = nearest;
          for (int i = 0; i < 500; ++i) {
            const Vec2 uv(3.0f * rng.nextFloat() - 1.0f, 3.0f * rng.nextFloat() - 1.0f);
            const Vec4 a = lookupTexture(byteScene, ref, uv, Vec2(0.0f), srgb);
            const Vec4 b = lookupTexture(floatScene, ref, uv, Vec2(0.0f), srgb);
            for (int k = 0; k < 4; ++k) ASSERT_EQ(a[k], b[k]) << "channels " << channels << " component " << k;
            ++compared;
          }
        }
      }
    }
  }
  EXPECT_EQ(compared, 4 * 3 * 2 * 2 * 500);
}

}  // namespace
}  // namespace tex::render
