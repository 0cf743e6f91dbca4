// Image decoding for the glTF loader: a tinygltf image callback that decodes PNG/JPEG with
// stb_image into floats and never fails the whole load (a bad image is a warning), after
// checking that an image's buffer view lies inside its buffer (tinygltf 2.7 does not).
#pragma once
#include <string>

#include <tiny_gltf.h>

namespace tex::render {

// tinygltf::LoadImageDataFunction; user data is a DecodedImages* (gltf_import.h).
bool decodeGltfImage(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn,
                     int requestedWidth, int requestedHeight, const unsigned char* bytes, int size, void* userData);

}  // namespace tex::render
