#include "renderer/scene/gltf_data_uris.h"

#include <cstdint>
#include <cstring>
#include <string_view>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

namespace tex::render {

namespace {

// What tinygltf's image parsing does with a data URI: it decodes it when it is one of the
// prefixes it knows, and fails the file when that gives no bytes.
bool undecodable(const std::string& uri) {
  if (!tinygltf::IsDataURI(uri)) return false;
  std::vector<unsigned char> data;
  std::string mime;
  return !tinygltf::DecodeDataURI(&data, mime, uri, 0, false);
}

void putU32(std::vector<unsigned char>& out, size_t at, uint32_t v) { std::memcpy(out.data() + at, &v, 4); }

}  // namespace

std::vector<int> replaceUndecodableImageUris(std::vector<unsigned char>& bytes, bool binary) {
  size_t jsonStart = 0, jsonSize = bytes.size();
  if (binary) {
    if (bytes.size() < 20) return {};
    uint32_t chunkLength = 0;
    std::memcpy(&chunkLength, bytes.data() + 12, 4);
    if (chunkLength > bytes.size() - 20) return {};
    jsonStart = 20;
    jsonSize = chunkLength;
  }
  // Only a document that spells "data" somewhere (or escapes characters, which could spell it)
  // can hold a data URI: skip parsing the others (a second full parse of the JSON had been a
  // quarter of loading a glTF file of 100k nodes).
  const std::string_view json(reinterpret_cast<const char*>(bytes.data()) + jsonStart, jsonSize);
  if (json.find("data") == std::string_view::npos && json.find("\\u") == std::string_view::npos) return {};
  nlohmann::json doc = nlohmann::json::parse(bytes.begin() + std::ptrdiff_t(jsonStart),
                                             bytes.begin() + std::ptrdiff_t(jsonStart + jsonSize), nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("images") || !doc["images"].is_array()) return {};
  std::vector<int> replaced;
  nlohmann::json& images = doc["images"];
  for (size_t i = 0; i < images.size(); ++i) {
    nlohmann::json& image = images[i];
    if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string() || image.contains("bufferView"))
      continue;
    if (!undecodable(image["uri"].get<std::string>())) continue;
    image["uri"] = kUndecodableDataUri;
    replaced.push_back(int(i));
  }
  if (replaced.empty()) return replaced;
  std::string text = doc.dump();
  if (!binary) {
    bytes.assign(text.begin(), text.end());
    return replaced;
  }
  while (text.size() % 4 != 0) text.push_back(' ');  // GLB chunks are 4-byte aligned, JSON padded with spaces
  std::vector<unsigned char> out(20 + text.size());
  std::memcpy(out.data(), bytes.data(), 12);
  putU32(out, 12, uint32_t(text.size()));
  std::memcpy(out.data() + 16, bytes.data() + 16, 4);  // the chunk type, "JSON"
  std::memcpy(out.data() + 20, text.data(), text.size());
  out.insert(out.end(), bytes.begin() + std::ptrdiff_t(20 + jsonSize), bytes.end());
  putU32(out, 8, uint32_t(out.size()));
  bytes = std::move(out);
  return replaced;
}

}  // namespace tex::render
