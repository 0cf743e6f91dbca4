// stb_image is linked from Debian's libstb (which holds the implementation; nothing in this
// repository defines STB_IMAGE_IMPLEMENTATION).
#include "renderer/scene/gltf_images.h"

#include <stb/stb_image.h>

#include "renderer/scene/gltf_import.h"

namespace tex::render {

namespace {

std::string imageLabel(const tinygltf::Image& image, int index) {
  std::string label = "image " + std::to_string(index);
  if (!image.name.empty()) label += " \"" + image.name + "\"";
  else if (!image.uri.empty() && image.uri.rfind("data:", 0) != 0) label += " (" + image.uri + ")";
  return label;
}

}  // namespace

bool decodeGltfImage(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* /*warn*/,
                     int, int, const unsigned char* bytes, int size, void* userData) {
  auto* decoded = static_cast<DecodedImages*>(userData);
  if (!decoded || !image) return false;
  if (image->bufferView >= 0 && decoded->model) {
    // tinygltf hands us buffer.data + byteOffset without a range check: check before reading.
    const tinygltf::Model& model = *decoded->model;
    const auto& view = model.bufferViews.at(size_t(image->bufferView));  // tinygltf checked the index
    const uint64_t bufferBytes = model.buffers.at(size_t(view.buffer)).data.size();
    if (uint64_t(view.byteOffset) > bufferBytes || uint64_t(view.byteLength) > bufferBytes - view.byteOffset) {
      if (err) *err += imageLabel(*image, imageIndex) + ": bufferView " + std::to_string(image->bufferView) + " lies outside its buffer\n";
      return false;
    }
  }
  if (!bytes || size <= 0) {
    decoded->failures[imageIndex] = "it has no data";
    return true;
  }
  int width = 0, height = 0, channels = 0;
  ImageData out;
  if (stbi_is_16_bit_from_memory(bytes, size)) {
    stbi_us* pixels = stbi_load_16_from_memory(bytes, size, &width, &height, &channels, 0);
    if (pixels) {
      out.pixels.resize(size_t(width) * size_t(height) * size_t(channels));
      for (size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = pixels[i] / 65535.0f;
      stbi_image_free(pixels);
    }
  } else {
    stbi_uc* pixels = stbi_load_from_memory(bytes, size, &width, &height, &channels, 0);
    if (pixels) {
      out.bytes.assign(pixels, pixels + size_t(width) * size_t(height) * size_t(channels));
      stbi_image_free(pixels);
    }
  }
  if (out.valueCount() == 0) {
    const char* reason = stbi_failure_reason();
    decoded->failures[imageIndex] = std::string("it could not be decoded: ") + (reason ? reason : "unknown format");
    return true;
  }
  out.name = image->name.empty() ? image->uri : image->name;
  if (out.name.rfind("data:", 0) == 0) out.name.clear();
  out.width = width;
  out.height = height;
  out.channels = channels;
  image->width = width;
  image->height = height;
  image->component = channels;
  decoded->byIndex[imageIndex] = std::move(out);
  return true;
}

void importImages(GltfImport& import, DecodedImages& decoded) {
  import.sceneImage.assign(import.model.images.size(), -1);
  for (size_t i = 0; i < import.model.images.size(); ++i) {
    auto it = decoded.byIndex.find(int(i));
    if (it == decoded.byIndex.end()) {
      auto failure = decoded.failures.find(int(i));
      const std::string why = failure != decoded.failures.end() ? failure->second : "its file is missing";
      import.warn(imageLabel(import.model.images[i], int(i)) + " has no pixels (" + why +
                  "); textures using it are ignored");
      continue;
    }
    import.sceneImage[i] = int(import.scene.images.size());
    import.scene.images.push_back(std::move(it->second));
  }
}

}  // namespace tex::render
