// Image I/O: EXR round trips are lossless for float, PNG round trips within 8-bit precision,
// and bad paths give messages naming the file.
#include "renderer/image/image_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <stb/stb_image_write.h>

namespace tex {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("tex_image_io_" + name)).string();
}

RgbImage gradient(int width, int height) {
  RgbImage image{width, height, std::vector<float>(size_t(width) * height * 3)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.rgb[(size_t(y) * width + x) * 3 + c] = float(x + 1) / width * float(c + 1) / 3.0f + 0.001f * y;
  return image;
}

TEST(ImageIo, ExrFloatRoundTripIsLosslessAndKeepsMetadata) {
  const std::string path = tempPath("rt.exr");
  RgbImage image = gradient(7, 5);
  image.rgb[4] = 1234.5678f;
  ASSERT_EQ(writeRgbImage(path, image, {{"tex.seed", "42"}, {"tex.integrator", "analytic"}}), "");
  RgbImage back;
  ASSERT_EQ(readRgbImage(path, back), "");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.rgb, image.rgb);
  ExrImage exr;
  ASSERT_EQ(readExr(path, exr), "");
  EXPECT_EQ(exr.metadata["tex.seed"], "42");
  EXPECT_EQ(exr.metadata["tex.integrator"], "analytic");
  std::filesystem::remove(path);
}

TEST(ImageIo, ExrHalfChannelsRoundTripWithinHalfPrecision) {
  const std::string path = tempPath("half.exr");
  ExrImage image;
  image.width = 4;
  image.height = 3;
  for (const char* name : {"R", "G", "B", "variance.R"}) {
    ExrChannel c{name, {}};
    for (int i = 0; i < 12; ++i) c.values.push_back(0.1f * i + 0.37f);
    image.channels.push_back(c);
  }
  ASSERT_EQ(writeExr(path, image, ExrPixelType::Half), "");
  ExrImage back;
  ASSERT_EQ(readExr(path, back), "");
  ASSERT_NE(back.find("variance.R"), nullptr);
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(back.find("variance.R")->values[i], 0.1f * i + 0.37f, 2e-3f);
  std::filesystem::remove(path);
}

TEST(ImageIo, PngRoundTripWithinEightBits) {
  const std::string path = tempPath("rt.png");
  RgbImage image = gradient(8, 4);
  ASSERT_EQ(writeRgbImage(path, image), "");
  RgbImage back;
  ASSERT_EQ(readRgbImage(path, back), "");
  ASSERT_EQ(back.rgb.size(), image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    float expected = std::min(image.rgb[i], 1.0f);
    EXPECT_NEAR(linearToSrgb(back.rgb[i]), linearToSrgb(expected), 0.5f / 255.0f + 1e-5f);
  }
  std::filesystem::remove(path);
}

// Radiance .hdr (environment maps are often shipped so): values above 1 survive, within the
// RGBE format's 8-bit mantissa; a PNG named .hdr and a truncated file are refused by name.
TEST(ImageIo, RadianceHdrReadsLinearValuesAboveOne) {
  const std::string path = tempPath("sky.hdr");
  RgbImage image = gradient(8, 4);
  for (float& v : image.rgb) v = v * 40.0f + 0.01f;
  ASSERT_NE(stbi_write_hdr(path.c_str(), image.width, image.height, 3, image.rgb.data()), 0);
  RgbImage back;
  ASSERT_EQ(readRgbImage(path, back), "");
  ASSERT_EQ(back.width, 8);
  ASSERT_EQ(back.height, 4);
  ASSERT_EQ(back.rgb.size(), image.rgb.size());
  float largest = 0.0f;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const float pixelMax = std::max({image.rgb[i / 3 * 3], image.rgb[i / 3 * 3 + 1], image.rgb[i / 3 * 3 + 2]});
    EXPECT_NEAR(back.rgb[i], image.rgb[i], pixelMax / 128.0f) << i;  // RGBE: a shared exponent, 8-bit mantissas
    largest = std::max(largest, back.rgb[i]);
  }
  EXPECT_GT(largest, 20.0f);
  const std::string png = tempPath("fake.hdr");
  ASSERT_EQ(writeRgbImage(tempPath("real.png"), gradient(2, 2)), "");
  std::filesystem::copy_file(tempPath("real.png"), png, std::filesystem::copy_options::overwrite_existing);
  const std::string error = readRgbImage(png, back);
  EXPECT_NE(error.find(png), std::string::npos) << error;
  EXPECT_NE(error.find("not a Radiance HDR file"), std::string::npos) << error;
  std::filesystem::resize_file(path, 40);
  const std::string truncated = readRgbImage(path, back);
  EXPECT_NE(truncated.find(path), std::string::npos) << truncated;
  // Cut inside the pixels, flat (width 4) or run-length encoded (width 40): stb_image alone
  // returned the missing part as black (a truncated sky lit a floor 2.2x too bright).
  for (const int width : {4, 40}) {
    RgbImage sky = gradient(width, 6);
    for (float& v : sky.rgb) v = v * 3.0f + 0.5f;
    ASSERT_NE(stbi_write_hdr(path.c_str(), sky.width, sky.height, 3, sky.rgb.data()), 0);
    ASSERT_EQ(readRgbImage(path, back), "") << width;
    std::filesystem::resize_file(path, std::filesystem::file_size(path) - 7);
    const std::string cut = readRgbImage(path, back);
    EXPECT_NE(cut.find("truncated"), std::string::npos) << width << ": " << cut;
  }
  // A run longer than the scanline's remaining width is malformed.
  {
    std::ofstream bad(path, std::ios::binary);
    bad << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n";
    const unsigned char scanline[] = {2, 2, 0, 8, 128 + 9, 7};
    bad.write(reinterpret_cast<const char*>(scanline), sizeof scanline);
  }
  const std::string longRun = readRgbImage(path, back);
  EXPECT_NE(longRun.find("past its width"), std::string::npos) << longRun;
  std::filesystem::remove(path);
  std::filesystem::remove(png);
  std::filesystem::remove(tempPath("real.png"));
}

TEST(ImageIo, ErrorsNameTheFile) {
  RgbImage image;
  std::string missing = tempPath("does_not_exist.exr");
  std::string error = readRgbImage(missing, image);
  EXPECT_NE(error.find(missing), std::string::npos) << error;
  const std::string garbage = tempPath("garbage.exr");
  FILE* f = std::fopen(garbage.c_str(), "wb");
  std::fputs("not an exr", f);
  std::fclose(f);
  error = readRgbImage(garbage, image);
  EXPECT_NE(error.find(garbage), std::string::npos) << error;
  std::filesystem::remove(garbage);
  EXPECT_NE(writeRgbImage("/nonexistent_dir/x.exr", gradient(2, 2)), "");
  EXPECT_NE(writeRgbImage(tempPath("x.bmp"), gradient(2, 2)), "");
  EXPECT_NE(writeRgbImage(tempPath("x.exr"), RgbImage{2, 2, {1.0f}}), "");
}

}  // namespace
}  // namespace tex
