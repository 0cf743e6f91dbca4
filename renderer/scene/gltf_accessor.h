// Checked reading of glTF accessors (tinygltf's model is parsed but not validated): every
// index, byte range, stride, component type and sparse substitution is checked before a
// byte is read, so a hostile file yields an error message and never an out-of-range read.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace tex::render {

// Which glTF component types an attribute may use (bit set of the kinds below).
enum AccessorComponents : unsigned {
  kFloatComponents = 1u << 0,
  kNormalizedUint8 = 1u << 1,   // normalized unsigned byte, read as value / 255
  kNormalizedUint16 = 1u << 2,  // normalized unsigned short, read as value / 65535
  kUnsignedIntegers = 1u << 3,  // uint8 / uint16 / uint32, read exactly (indices)
  // KHR_mesh_quantization's types for vertex attributes:
  kNormalizedInt8 = 1u << 4,    // normalized signed byte, read as max(value / 127, -1)
  kNormalizedInt16 = 1u << 5,   // normalized signed short, read as max(value / 32767, -1)
  kSmallIntegers = 1u << 6,     // int8 / uint8 / int16 / uint16 unnormalized, read exactly
};
// What KHR_mesh_quantization allows for positions and texture coordinates (every 8- and 16-bit
// type, normalized or not), and for normals, tangents and their displacements (normalized
// signed ones).
constexpr unsigned kQuantizedCoordinates =
    kFloatComponents | kNormalizedUint8 | kNormalizedUint16 | kNormalizedInt8 | kNormalizedInt16 | kSmallIntegers;
constexpr unsigned kQuantizedDirections = kFloatComponents | kNormalizedInt8 | kNormalizedInt16;

// Reads accessor `index` of element type `type` (TINYGLTF_TYPE_VEC3, ...) into `out` as
// count * components floats. Returns "" or a message describing the problem (no file name).
std::string readFloatAccessor(const tinygltf::Model& model, int index, int type,
                              unsigned allowedComponents, std::vector<float>& out);

// Reads a SCALAR accessor of unsigned integers (indices) into `out`.
std::string readIndexAccessor(const tinygltf::Model& model, int index, std::vector<uint32_t>& out);

}  // namespace tex::render
