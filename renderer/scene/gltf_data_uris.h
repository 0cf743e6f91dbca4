// Image data URIs that tinygltf cannot decode (not base64, or empty) fail its whole parse, while
// glTF's rule for an image that cannot be read is a warning and the material's factors. Before
// tinygltf sees the file, such URIs are replaced by a name that reads as a missing file.
#pragma once
#include <string>
#include <vector>

namespace tex::render {

// The name an undecodable data URI is replaced by (tinygltf's warnings about it are dropped).
inline constexpr const char* kUndecodableDataUri = "undecodable data URI";

// Rewrites the images' undecodable data URIs in `bytes` (a .gltf's text, or a .glb whose first
// chunk is its JSON) and returns the indices of the images rewritten; `bytes` is unchanged when
// there are none or the JSON does not parse (tinygltf then reports it).
std::vector<int> replaceUndecodableImageUris(std::vector<unsigned char>& bytes, bool binary);

}  // namespace tex::render
