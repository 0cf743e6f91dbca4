// OpenEXR and PNG reading and writing. OpenEXR throws; every entry point catches and turns
// the exception into a message naming the file.
#include "renderer/image/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <Imath/half.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iterator>
#include <set>

namespace tex {

namespace {

std::string lowerExtension(const std::string& path) {
  size_t dot = path.find_last_of('.');
  size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Attribute names OpenEXR reserves for itself; user metadata never overwrites them.
bool isReservedAttribute(const std::string& name) {
  static const std::set<std::string> reserved = {
      "channels", "compression", "dataWindow", "displayWindow", "lineOrder",
      "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth", "tiles", "type",
      "name", "version", "chunkCount", "maxSamplesPerPixel"};
  return reserved.count(name) != 0;
}

std::string checkSize(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) {
    return path + ": cannot write an image of size " + std::to_string(width) + "x" +
           std::to_string(height);
  }
  return "";
}

std::string writePng(const std::string& path, const RgbImage& image) {
  std::vector<unsigned char> bytes(size_t(image.width) * image.height * 3);
  for (size_t i = 0; i < bytes.size(); ++i) {
    float v = linearToSrgb(image.rgb[i]);
    if (!(v >= 0.0f)) v = 0.0f;  // also maps NaN to black
    if (v > 1.0f) v = 1.0f;
    bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
  }
  if (stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(), image.width * 3) == 0) {
    return path + ": cannot write PNG (directory missing or not writable?)";
  }
  return "";
}

// Readers open only regular files: opening a FIFO blocks until a writer appears (tex develop and
// tex compare hung on one), and a directory or device is no image either.
static std::string notARegularFile(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) return "";  // the reader reports a missing file itself
  return std::filesystem::is_regular_file(status) ? "" : path + ": not a regular file";
}

std::string readPng(const std::string& path, RgbImage& out) {
  if (std::string e = notARegularFile(path); !e.empty()) return e;
  int width = 0, height = 0, channelsInFile = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channelsInFile, 3);
  if (data == nullptr) {
    const char* reason = stbi_failure_reason();
    return path + ": cannot read PNG: " + (reason ? reason : "unknown error");
  }
  out.width = width;
  out.height = height;
  out.rgb.resize(size_t(width) * height * 3);
  for (size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = srgbToLinear(data[i] / 255.0f);
  stbi_image_free(data);
  return "";
}

// Walks a Radiance file's scanlines as stb_image will decode them and says what is missing or
// malformed: stb_image reads past the end of a truncated file as zeros and returns a picture
// (half a sky came back black, random bytes a sky of 1e9), so the structure is checked first.
// Scanlines are flat RGBE or the new run-length encoding (4, then the width, then each channel
// as runs: a count above 128 repeats the next byte count - 128 times, else count bytes follow).
std::string checkRadianceHdrData(const std::vector<unsigned char>& bytes) {
  size_t at = 0;
  auto line = [&](std::string& text) {
    text.clear();
    while (at < bytes.size() && bytes[at] != '\n') text += char(bytes[at++]);
    if (at >= bytes.size()) return false;
    ++at;
    return true;
  };
  std::string text;
  do {
    if (!line(text)) return "the header does not end";
  } while (!text.empty());
  if (!line(text)) return "no resolution line";
  int height = 0, width = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "-Y %d +X %d%c", &height, &width, &rest) != 2 || width <= 0 || height <= 0)
    return "unsupported resolution line \"" + text + "\" (expected \"-Y height +X width\")";
  for (int y = 0; y < height; ++y) {
    const std::string where = "scanline " + std::to_string(y) + " of " + std::to_string(height);
    const bool rle = width >= 8 && width < 32768 && at + 4 <= bytes.size() && bytes[at] == 2 && bytes[at + 1] == 2 &&
                     ((int(bytes[at + 2]) << 8) | bytes[at + 3]) == width;
    if (!rle) {  // stb_image then reads this and every later scanline flat
      const size_t complete = (bytes.size() - at) / 4 / size_t(width);
      if (complete < size_t(height - y))
        return "the pixels stop in scanline " + std::to_string(y + complete) + " of " + std::to_string(height) + " (the file is truncated)";
      return "";
    }
    at += 4;
    for (int c = 0; c < 4; ++c) {
      for (int x = 0; x < width;) {
        if (at >= bytes.size()) return where + " is cut short (the file is truncated)";
        int count = bytes[at++];
        const bool run = count > 128;
        if (run) count -= 128;
        if (count == 0 || count > width - x) return where + " has a run of " + std::to_string(count) + " past its width";
        const size_t need = run ? 1 : size_t(count);
        if (bytes.size() - at < need) return where + " is cut short (the file is truncated)";
        at += need;
        x += count;
      }
    }
  }
  return "";
}

// Radiance RGBE (.hdr), as HDR environment maps are commonly shipped: linear floats.
std::string readRadianceHdr(const std::string& path, RgbImage& out) {
  if (std::string e = notARegularFile(path); !e.empty()) return e;
  if (!stbi_is_hdr(path.c_str())) {
    const char* reason = stbi_failure_reason();
    return path + ": not a Radiance HDR file" + (reason ? std::string(" (") + reason + ")" : std::string());
  }
  {
    std::ifstream file(path, std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const std::string problem = checkRadianceHdrData(bytes);
    if (!problem.empty()) return path + ": malformed Radiance HDR: " + problem;
  }
  int width = 0, height = 0, channelsInFile = 0;
  float* data = stbi_loadf(path.c_str(), &width, &height, &channelsInFile, 3);
  if (data == nullptr) {
    const char* reason = stbi_failure_reason();
    return path + ": cannot read Radiance HDR: " + (reason ? reason : "unknown error");
  }
  out.width = width;
  out.height = height;
  out.rgb.assign(data, data + size_t(width) * height * 3);
  stbi_image_free(data);
  return "";
}

}  // namespace

float linearToSrgb(float linear) {
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float encoded) {
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

const ExrChannel* ExrImage::find(const std::string& name) const {
  for (const ExrChannel& c : channels) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string writeExr(const std::string& path, const ExrImage& image, ExrPixelType pixelType) {
  if (std::string e = checkSize(path, image.width, image.height); !e.empty()) return e;
  const size_t pixelCount = size_t(image.width) * image.height;
  if (image.channels.empty()) return path + ": cannot write an EXR without channels";
  for (const ExrChannel& c : image.channels) {
    if (c.values.size() != pixelCount) {
      return path + ": channel '" + c.name + "' has " + std::to_string(c.values.size()) +
             " values, expected " + std::to_string(pixelCount);
    }
  }
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const Imf::PixelType fileType = pixelType == ExrPixelType::Half ? Imf::HALF : Imf::FLOAT;
    Imf::FrameBuffer frameBuffer;
    // OpenEXR's output file does not convert pixel types: half channels get half buffers.
    std::vector<std::vector<half>> halfBuffers;
    if (fileType == Imf::HALF) {
      for (const ExrChannel& c : image.channels) halfBuffers.emplace_back(c.values.begin(), c.values.end());
    }
    for (size_t k = 0; k < image.channels.size(); ++k) {
      const ExrChannel& c = image.channels[k];
      header.channels().insert(c.name, Imf::Channel(fileType));
      if (fileType == Imf::HALF) {
        frameBuffer.insert(c.name, Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halfBuffers[k].data()),
                                              sizeof(half), sizeof(half) * size_t(image.width)));
      } else {
        frameBuffer.insert(c.name, Imf::Slice(Imf::FLOAT, (char*)c.values.data(), sizeof(float),
                                              sizeof(float) * size_t(image.width)));
      }
    }
    for (const auto& [key, value] : image.metadata) {
      if (key.empty() || isReservedAttribute(key)) continue;
      header.insert(key, Imf::StringAttribute(value));
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frameBuffer);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    return path + ": cannot write OpenEXR: " + e.what();
  }
  return "";
}

std::string readExr(const std::string& path, ExrImage& out) {
  if (std::string e = notARegularFile(path); !e.empty()) return e;
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i dw = header.dataWindow();
    const long width = long(dw.max.x) - dw.min.x + 1;
    const long height = long(dw.max.y) - dw.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > (long(1) << 31)) {
      return path + ": OpenEXR data window is empty or too large";
    }
    ExrImage image;
    image.width = int(width);
    image.height = int(height);
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1) {
        return path + ": channel '" + it.name() + "' is subsampled; only full-resolution channels are supported";
      }
      image.channels.push_back({it.name(), std::vector<float>(size_t(width) * height, 0.0f)});
    }
    Imf::FrameBuffer frameBuffer;
    for (ExrChannel& c : image.channels) {
      // Base pointer is offset so that (dw.min.x, dw.min.y) lands on element 0.
      char* base = reinterpret_cast<char*>(c.values.data()) -
                   (long(dw.min.x) + long(dw.min.y) * width) * long(sizeof(float));
      frameBuffer.insert(c.name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * width));
    }
    file.setFrameBuffer(frameBuffer);
    file.readPixels(dw.min.y, dw.max.y);
    for (auto it = header.begin(); it != header.end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
        image.metadata[it.name()] = s->value();
      }
    }
    out = std::move(image);
  } catch (const std::exception& e) {
    return path + ": cannot read OpenEXR: " + e.what();
  }
  return "";
}

std::string writeRgbImage(const std::string& path, const RgbImage& image,
                          const std::map<std::string, std::string>& metadata) {
  if (std::string e = checkSize(path, image.width, image.height); !e.empty()) return e;
  const size_t pixelCount = size_t(image.width) * image.height;
  if (image.rgb.size() != pixelCount * 3) {
    return path + ": image has " + std::to_string(image.rgb.size()) + " floats, expected " +
           std::to_string(pixelCount * 3);
  }
  const std::string ext = lowerExtension(path);
  if (ext == "png") return writePng(path, image);
  if (ext != "exr") return path + ": unknown image extension '." + ext + "' (use .exr or .png)";
  ExrImage exr;
  exr.width = image.width;
  exr.height = image.height;
  exr.metadata = metadata;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    ExrChannel channel{names[c], std::vector<float>(pixelCount)};
    for (size_t i = 0; i < pixelCount; ++i) channel.values[i] = image.rgb[i * 3 + c];
    exr.channels.push_back(std::move(channel));
  }
  return writeExr(path, exr, ExrPixelType::Float);
}

std::string readRgbImage(const std::string& path, RgbImage& out) {
  const std::string ext = lowerExtension(path);
  if (ext == "png") return readPng(path, out);
  if (ext == "hdr") return readRadianceHdr(path, out);
  ExrImage exr;
  if (std::string e = readExr(path, exr); !e.empty()) return e;
  const ExrChannel* r = exr.find("R");
  const ExrChannel* g = exr.find("G");
  const ExrChannel* b = exr.find("B");
  if (r == nullptr) r = exr.find("Y");  // luminance-only files
  if (r == nullptr) return path + ": OpenEXR file has no R (or Y) channel";
  if (g == nullptr) g = r;
  if (b == nullptr) b = r;
  const size_t pixelCount = size_t(exr.width) * exr.height;
  out.width = exr.width;
  out.height = exr.height;
  out.rgb.resize(pixelCount * 3);
  for (size_t i = 0; i < pixelCount; ++i) {
    out.rgb[i * 3 + 0] = r->values[i];
    out.rgb[i * 3 + 1] = g->values[i];
    out.rgb[i * 3 + 2] = b->values[i];
  }
  return "";
}

}  // namespace tex
