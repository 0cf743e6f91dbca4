// Decoded image textures (docs/stdlib.md, "Image textures"): a process-wide, thread-safe,
// never-shrinking table of images addressed by int32 handles, and the lookups that both the
// interpreter and compiled code call (so the two agree bit for bit).
#pragma once
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

namespace tex::lang {

// Wrap modes: the values of the builtin constants wrap_repeat, wrap_clamp, wrap_mirror.
// Any other value wraps as repeat.
enum class ImageWrap : int32_t { Repeat = 0, Clamp = 1, Mirror = 2 };
enum class ImageFilter : int32_t { Nearest = 0, Bilinear = 1, Trilinear = 2 };

// One mip level, row-major, top row first (v = 0 is the top edge): linear RGBA floats, or (a
// PNG's level 0) the file's 8- or 16-bit RGBA codes as stored, decoded per lookup through one
// table per channel. The tables hold exactly the floats decoding at load gave, so lookups are
// the same bits, at a quarter (8-bit) or half (16-bit) of the memory: an 8192^2 PNG's level 0
// takes 256 MB, where floats took 1 GB (its float mips take another 341 MB).
struct ImageLevel {
  int32_t width = 0, height = 0;
  std::vector<float> rgba;        // float levels (OpenEXR files, mips)
  std::vector<uint8_t> codes8;    // 8-bit PNG codes, RGBA
  std::vector<uint16_t> codes16;  // 16-bit PNG codes, RGBA
  const float* decode[4] = {};    // encoded levels: code -> linear value, per channel (static tables)

  // Texel `index` (y * width + x) as linear RGBA.
  void texel(size_t index, float out[4]) const {
    const size_t i = index * 4;
    if (!codes8.empty()) {
      for (int c = 0; c < 4; ++c) out[c] = decode[c][codes8[i + size_t(c)]];
    } else if (!codes16.empty()) {
      for (int c = 0; c < 4; ++c) out[c] = decode[c][codes16[i + size_t(c)]];
    } else {
      for (int c = 0; c < 4; ++c) out[c] = rgba[i + size_t(c)];
    }
  }
  // Every texel as linear RGBA floats (what `rgba` holds for float levels).
  std::vector<float> decoded() const;
  // The memory the texels take.
  size_t texelBytes() const { return rgba.size() * sizeof(float) + codes8.size() + codes16.size() * sizeof(uint16_t); }
};

struct LoadedImage {
  std::string path;         // canonical absolute path
  bool data = false;        // image_data(): 8/16-bit values kept as they are (no sRGB decode)
  uint64_t fileBytes = 0;   // the file's identity when loaded (cache keys, reload on change)
  int64_t mtimeNs = 0;
  std::vector<ImageLevel> levels;  // levels[0] is the file; each next one half size, down to 1x1
};

struct ImageLoadResult {
  int32_t handle = -1;  // >= 0 on success
  std::string code;     // on failure: E0420 missing or unreadable, E0421 unsupported or corrupt
  std::string message;
};

class ImageTable {
 public:
  static ImageTable& global();

  // Loads `path` (or returns the handle of its earlier load if the file's size and mtime are
  // unchanged; a changed file gets a new handle, old handles stay valid). Thread-safe.
  ImageLoadResult load(const std::string& path, bool data);
  // The handle this process loaded for `canonicalPath` (as LoadedImage::path) when the file had
  // `fileBytes` and `mtimeNs`, so that a value made before the file changed keeps its image
  // (language.md); else the latest, loading it if this process has not yet; -1 if that fails.
  // For compiled code, whose handles are resolved at run time (docs/abi.md, "Images").
  int32_t resolve(const std::string& canonicalPath, bool data, uint64_t fileBytes, int64_t mtimeNs);
  // Lock-free; null for a handle that was never returned.
  const LoadedImage* get(int32_t handle) const;
  // The canonical paths of every file this process has loaded (for output-collision checks).
  std::vector<std::string> paths();

  static constexpr int kChunkBits = 8;
  static constexpr int kChunks = 256;  // at most 65536 images per process

 private:
  ImageTable() = default;
  struct Chunk {
    std::atomic<const LoadedImage*> slots[1 << kChunkBits] = {};
  };
  std::mutex mutex_;
  std::atomic<Chunk*> chunks_[kChunks] = {};
  int32_t count_ = 0;                                    // under mutex_
  std::map<std::pair<std::string, bool>, int32_t> byPath_;  // under mutex_: the latest load
  // Every load by its file's identity (path, data, bytes, mtime), under mutex_.
  std::map<std::tuple<std::string, bool, uint64_t, int64_t>, int32_t> byVersion_;
  std::vector<std::unique_ptr<LoadedImage>> owned_;      // under mutex_
  std::vector<std::unique_ptr<Chunk>> ownedChunks_;      // under mutex_
};

// Decodes a PNG (stb_image; sRGB to linear unless `data`) or OpenEXR (always linear) file into
// level 0. On failure returns false with `code` and `message` as in ImageLoadResult.
bool decodeImageFile(const std::string& path, bool data, ImageLevel& out, std::string& code, std::string& message);
// The mip pyramid of `base`: box-filtered halvings down to 1x1 (levels[0] is `base`).
std::vector<ImageLevel> buildMipPyramid(ImageLevel base);
// The sRGB transfer function's inverse (IEC 61966-2-1), for an encoded value in [0, 1].
float srgbToLinear(float encoded);

// RGBA at (u, v) of `image`. Nearest and Bilinear use level 0; Trilinear picks the level from
// the screen-space derivatives of uv (isotropic, as in the OpenGL 4.6 specification, 8.14:
// rho = the longer footprint axis in level-0 texels, lod = log2 rho) and blends the two
// nearest levels. Non-finite coordinates give zeros.
void lookupImage(const LoadedImage& image, ImageFilter filter, int32_t wrap, float u, float v, float dudx, float dvdx,
                 float dudy, float dvdy, float out[4]);
// The same through the global table; an invalid handle gives zeros.
void imageLookup(int32_t handle, ImageFilter filter, int32_t wrap, float u, float v, float dudx, float dvdx, float dudy,
                 float dvdy, float out[4]);
// (width, height) of level 0, or (0, 0) for an invalid handle.
void imageSize(int32_t handle, float out[2]);

}  // namespace tex::lang
