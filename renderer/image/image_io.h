// Image files: OpenEXR (through the OpenEXR library), Radiance .hdr for reading environment
// maps, and PNG (through stb) for quick looks.
// Pixels are linear sRGB floats, row-major, top row first. Errors are returned as messages
// that name the file and the problem; an empty string means success. Nothing here throws.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace tex {

// Linear sRGB, row-major, top row first, 3 floats per pixel (size = width * height * 3).
struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

// Writes by extension: .exr (OpenEXR, float RGB, metadata as string attributes) or .png
// (sRGB-encoded 8-bit via stb, clamped to [0,1]; metadata ignored).
std::string writeRgbImage(const std::string& path, const RgbImage& image,
                          const std::map<std::string, std::string>& metadata = {});

// Reads an RGB(A) OpenEXR (missing G/B channels repeat R, as for a luminance file), a Radiance
// RGBE .hdr (linear, through stb), or a PNG (decoded from sRGB to linear).
std::string readRgbImage(const std::string& path, RgbImage& out);

// ---- Multi-channel OpenEXR (the film's developed output, with extra layers) --------------

enum class ExrPixelType { Float, Half };

// One scalar channel of width * height values, row-major, top row first.
struct ExrChannel {
  std::string name;  // e.g. "R", "variance.R", "spectral.560nm"
  std::vector<float> values;
};

struct ExrImage {
  int width = 0, height = 0;
  std::vector<ExrChannel> channels;
  std::map<std::string, std::string> metadata;  // string attributes of the header

  // The channel with this name, or nullptr.
  const ExrChannel* find(const std::string& name) const;
};

// Writes every channel with the given pixel type (ZIP compression) and the metadata as
// string attributes. Channel sizes must equal width * height.
std::string writeExr(const std::string& path, const ExrImage& image,
                     ExrPixelType pixelType = ExrPixelType::Float);

// Reads every channel (converted to float) and every string attribute of the header.
std::string readExr(const std::string& path, ExrImage& out);

// sRGB transfer function and its inverse, for one channel value.
float linearToSrgb(float linear);
float srgbToLinear(float encoded);

}  // namespace tex
