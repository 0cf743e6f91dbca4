// The image table, file decoding (PNG through stb_image, OpenEXR through the OpenEXR 3
// library) and the mip pyramid.
#include "lang/image_table.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <ImfRgbaFile.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>

namespace tex::lang {

namespace fs = std::filesystem;

ImageTable& ImageTable::global() {
  static ImageTable table;
  return table;
}

const LoadedImage* ImageTable::get(int32_t handle) const {
  if (handle < 0 || handle >= kChunks << kChunkBits) return nullptr;
  const Chunk* chunk = chunks_[handle >> kChunkBits].load(std::memory_order_acquire);
  if (!chunk) return nullptr;
  return chunk->slots[handle & ((1 << kChunkBits) - 1)].load(std::memory_order_acquire);
}

ImageLoadResult ImageTable::load(const std::string& rawPath, bool data) {
  ImageLoadResult result;
  std::error_code ec;
  fs::path path = fs::weakly_canonical(fs::absolute(rawPath, ec), ec);
  if (ec) path = rawPath;
  auto status = fs::status(path, ec);
  if (ec || !fs::is_regular_file(status)) {
    result.code = "E0420";
    result.message = !ec && fs::is_directory(status) ? "image file '" + rawPath + "' is a directory"
                                                     : "image file '" + rawPath + "' not found";
    return result;
  }
  uint64_t bytes = fs::file_size(path, ec);
  int64_t mtime = ec ? 0 : int64_t(fs::last_write_time(path, ec).time_since_epoch().count());
  // Decoding happens under the lock: a file is decoded once even when many threads ask.
  std::lock_guard<std::mutex> lock(mutex_);
  auto key = std::make_pair(path.string(), data);
  if (auto it = byPath_.find(key); it != byPath_.end()) {
    const LoadedImage* known = get(it->second);
    if (known->fileBytes == bytes && known->mtimeNs == mtime) {
      result.handle = it->second;
      return result;
    }
  }
  if (count_ >= kChunks << kChunkBits) {
    result.code = "E0421";
    result.message = "too many images loaded in this process";
    return result;
  }
  auto image = std::make_unique<LoadedImage>();
  image->path = path.string();
  image->data = data;
  image->fileBytes = bytes;
  image->mtimeNs = mtime;
  ImageLevel base;
  if (!decodeImageFile(image->path, data, base, result.code, result.message)) return result;
  image->levels = buildMipPyramid(std::move(base));
  int32_t handle = count_++;
  std::atomic<Chunk*>& chunkSlot = chunks_[handle >> kChunkBits];
  Chunk* chunk = chunkSlot.load(std::memory_order_relaxed);
  if (!chunk) {
    ownedChunks_.push_back(std::make_unique<Chunk>());
    chunk = ownedChunks_.back().get();
    chunkSlot.store(chunk, std::memory_order_release);
  }
  chunk->slots[handle & ((1 << kChunkBits) - 1)].store(image.get(), std::memory_order_release);
  owned_.push_back(std::move(image));
  byPath_[key] = handle;
  byVersion_[std::make_tuple(key.first, data, bytes, mtime)] = handle;
  result.handle = handle;
  return result;
}

std::vector<std::string> ImageTable::paths() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [key, handle] : byPath_) out.push_back(key.first);
  return out;
}

int32_t ImageTable::resolve(const std::string& canonicalPath, bool data, uint64_t fileBytes, int64_t mtimeNs) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = byVersion_.find(std::make_tuple(canonicalPath, data, fileBytes, mtimeNs)); it != byVersion_.end())
      return it->second;
    if (auto it = byPath_.find(std::make_pair(canonicalPath, data)); it != byPath_.end()) return it->second;
  }
  return load(canonicalPath, data).handle;
}

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

namespace {

bool hasPrefix(const std::string& head, const char* magic, size_t n) {
  return head.size() >= n && std::memcmp(head.data(), magic, n) == 0;
}

// The value of every 8- or 16-bit code: srgbToLinear(code x 1/255 or 1/65535), or the scaled
// code itself (data images and alpha). Tables, not a pow per channel (40 % of loading an 8k PNG
// had been powf), and the texels keep their codes (ImageLevel::decode).
const std::vector<float>& codeTable(bool sixteen, bool srgb) {
  const auto build = [](size_t codes, bool srgb) {
    std::vector<float> table(codes);
    const float scale = codes == 256 ? 1.0f / 255.0f : 1.0f / 65535.0f;
    for (size_t i = 0; i < codes; ++i) table[i] = srgb ? srgbToLinear(float(i) * scale) : float(i) * scale;
    return table;
  };
  static const std::vector<float> tables[2][2] = {{build(256, false), build(256, true)},
                                                  {build(65536, false), build(65536, true)}};
  return tables[sixteen][srgb];
}

bool decodePng(const std::string& path, bool data, ImageLevel& out, std::string& message) {
  int w = 0, h = 0, channels = 0;
  bool sixteen = stbi_is_16_bit(path.c_str()) != 0;
  void* pixels = sixteen ? static_cast<void*>(stbi_load_16(path.c_str(), &w, &h, &channels, 4))
                         : static_cast<void*>(stbi_load(path.c_str(), &w, &h, &channels, 4));
  if (!pixels) {
    const char* why = stbi_failure_reason();
    message = std::string("cannot decode PNG: ") + (why ? why : "unknown error");
    return false;
  }
  out.width = w;
  out.height = h;
  const size_t count = size_t(w) * size_t(h) * 4;
  if (sixteen) out.codes16.assign(static_cast<uint16_t*>(pixels), static_cast<uint16_t*>(pixels) + count);
  else out.codes8.assign(static_cast<uint8_t*>(pixels), static_cast<uint8_t*>(pixels) + count);
  for (int c = 0; c < 4; ++c) out.decode[c] = codeTable(sixteen, !data && c < 3).data();  // alpha is linear coverage in PNG
  stbi_image_free(pixels);
  return true;
}

// Luminance and luminance-chroma files (Y, RY, BY): RgbaInputFile converts them to RGBA (in
// half precision, which is what such files store).
bool decodeExrLuminance(const std::string& path, ImageLevel& out) {
  Imf::RgbaInputFile file(path.c_str());
  const Imath::Box2i window = file.dataWindow();
  const int w = window.max.x - window.min.x + 1, h = window.max.y - window.min.y + 1;
  std::vector<Imf::Rgba> pixels(size_t(w) * size_t(h));
  file.setFrameBuffer(pixels.data() - window.min.x - int64_t(window.min.y) * w, 1, size_t(w));
  file.readPixels(window.min.y, window.max.y);
  const bool hasAlpha = (file.channels() & Imf::WRITE_A) != 0;
  out.width = w;
  out.height = h;
  out.rgba.resize(pixels.size() * 4);
  for (size_t i = 0; i < pixels.size(); ++i) {
    out.rgba[4 * i + 0] = float(pixels[i].r);
    out.rgba[4 * i + 1] = float(pixels[i].g);
    out.rgba[4 * i + 2] = float(pixels[i].b);
    out.rgba[4 * i + 3] = hasAlpha ? float(pixels[i].a) : 1.0f;
  }
  return true;
}

bool decodeExr(const std::string& path, ImageLevel& out, std::string& message) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t w = int64_t(window.max.x) - window.min.x + 1;
    const int64_t h = int64_t(window.max.y) - window.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > (int64_t(1) << 28)) {
      message = "OpenEXR image has an unusable size";
      return false;
    }
    const Imf::ChannelList& channels = file.header().channels();
    const char* names[4] = {"R", "G", "B", "A"};
    bool anyColour = false, subsampled = false;
    for (int c = 0; c < 4; ++c)
      if (const Imf::Channel* ch = channels.findChannel(names[c])) {
        anyColour |= c < 3;
        subsampled |= ch->xSampling != 1 || ch->ySampling != 1;
      }
    const Imf::Channel* luminance = channels.findChannel("Y");
    const bool chroma = channels.findChannel("RY") != nullptr || channels.findChannel("BY") != nullptr;
    if (!anyColour && !luminance) {
      std::string names;
      for (auto it = channels.begin(); it != channels.end(); ++it) names += std::string(names.empty() ? "" : ", ") + it.name();
      message = "OpenEXR image has no R, G, B or Y channel (it has: " + (names.empty() ? std::string("none") : names) + ")";
      return false;
    }
    // Subsampled colour or chroma (RY, BY): RgbaInputFile reconstructs RGB, in half precision.
    if (subsampled || (!anyColour && (chroma || luminance->xSampling != 1 || luminance->ySampling != 1)))
      return decodeExrLuminance(path, out);
    // R, G, B, A (or Y into all three) read as 32-bit floats whatever their storage (half,
    // float or uint), so float files keep their precision and values beyond half's range
    // (65504). A missing colour channel reads 0, a missing alpha 1.
    out.width = int(w);
    out.height = int(h);
    out.rgba.assign(size_t(w) * size_t(h) * 4, 0.0f);
    Imf::FrameBuffer frameBuffer;
    char* origin = reinterpret_cast<char*>(out.rgba.data()) -
                   (int64_t(window.min.x) + int64_t(window.min.y) * w) * int64_t(4 * sizeof(float));
    const char* source[4] = {"R", "G", "B", "A"};
    if (!anyColour) source[0] = source[1] = source[2] = "Y";
    // One slice per channel name: Y goes to R, then is copied to G and B below.
    for (int c = 0; c < 4; ++c) {
      if (!anyColour && (c == 1 || c == 2)) continue;
      frameBuffer.insert(source[c], Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), 4 * sizeof(float),
                                               size_t(w) * 4 * sizeof(float), 1, 1, c == 3 ? 1.0 : 0.0));
    }
    file.setFrameBuffer(frameBuffer);
    file.readPixels(window.min.y, window.max.y);
    if (!anyColour)
      for (size_t i = 0; i < out.rgba.size(); i += 4) out.rgba[i + 1] = out.rgba[i + 2] = out.rgba[i];
    return true;
  } catch (const std::exception& e) {
    message = std::string("cannot decode OpenEXR: ") + e.what();
    return false;
  }
}

}  // namespace

bool decodeImageFile(const std::string& path, bool data, ImageLevel& out, std::string& code, std::string& message) {
  std::ifstream in(path, std::ios::binary);
  std::string head(8, '\0');
  if (!in || !in.read(head.data(), 8)) {
    if (!in.is_open()) {
      code = "E0420";
      message = "cannot read image file '" + path + "'";
      return false;
    }
    head.resize(size_t(in.gcount()));
  }
  bool ok;
  if (hasPrefix(head, "\x89PNG\r\n\x1a\n", 8)) ok = decodePng(path, data, out, message);
  else if (hasPrefix(head, "\x76\x2f\x31\x01", 4)) ok = decodeExr(path, out, message);
  else {
    code = "E0421";
    message = "unsupported image format in '" + path + "' (expected PNG or OpenEXR)";
    return false;
  }
  if (!ok) {
    code = "E0421";
    message += " ('" + path + "')";
  }
  return ok;
}

std::vector<float> ImageLevel::decoded() const {
  std::vector<float> out(size_t(width) * size_t(height) * 4);
  for (size_t i = 0; i < out.size() / 4; ++i) texel(i, &out[i * 4]);
  return out;
}

// Each texel of the next level averages the block of texels it covers: [floor(i*w/w'),
// floor((i+1)*w/w')) in each axis, so odd sizes still average every texel exactly once.
std::vector<ImageLevel> buildMipPyramid(ImageLevel base) {
  std::vector<ImageLevel> levels;
  levels.push_back(std::move(base));
  while (levels.back().width > 1 || levels.back().height > 1) {
    const ImageLevel& src = levels.back();
    ImageLevel dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    dst.rgba.assign(size_t(dst.width) * size_t(dst.height) * 4, 0.0f);
    for (int32_t y = 0; y < dst.height; ++y) {
      int32_t y0 = int32_t(int64_t(y) * src.height / dst.height), y1 = int32_t(int64_t(y + 1) * src.height / dst.height);
      for (int32_t x = 0; x < dst.width; ++x) {
        int32_t x0 = int32_t(int64_t(x) * src.width / dst.width), x1 = int32_t(int64_t(x + 1) * src.width / dst.width);
        double sum[4] = {0, 0, 0, 0};
        for (int32_t sy = y0; sy < y1; ++sy)
          for (int32_t sx = x0; sx < x1; ++sx) {
            float t[4];
            src.texel(size_t(sy) * size_t(src.width) + size_t(sx), t);
            for (int c = 0; c < 4; ++c) sum[c] += t[c];
          }
        double count = double(y1 - y0) * double(x1 - x0);
        for (int c = 0; c < 4; ++c) dst.rgba[(size_t(y) * size_t(dst.width) + size_t(x)) * 4 + size_t(c)] = float(sum[c] / count);
      }
    }
    levels.push_back(std::move(dst));
  }
  return levels;
}

}  // namespace tex::lang
