// Checked glTF accessor reading. Layout rules: glTF 2.0 specification, section 3.6
// ("Buffers, buffer views and accessors") and 3.6.2.3 (sparse accessors).
#include "renderer/scene/gltf_accessor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace tex::render {

namespace {

// Accessors without a buffer view (all zeros, or sparse only) are not bounded by any buffer;
// refuse absurd element counts before allocating.
// (A 740-byte file with a 2^27-element POSITION accessor and no bufferView took 12 GB.)
constexpr uint64_t kMaxUnbackedElements = uint64_t(1) << 22;

int componentBytes(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    default: return "a matrix or unknown type";
  }
}

bool componentAllowed(int componentType, bool normalized, unsigned allowed) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return allowed & kFloatComponents;
    // kUnsignedIntegers (indices) are never normalized (glTF 2.0, 3.7.2.1).
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? (allowed & kNormalizedUint8) : (allowed & (kUnsignedIntegers | kSmallIntegers));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return normalized ? (allowed & kNormalizedUint16) : (allowed & (kUnsignedIntegers | kSmallIntegers));
    case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? (allowed & kNormalizedInt8) : (allowed & kSmallIntegers);
    case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? (allowed & kNormalizedInt16) : (allowed & kSmallIntegers);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return !normalized && (allowed & kUnsignedIntegers);
    default: return false;
  }
}

double decodeComponent(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const int8_t v = int8_t(p[0]);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0;
  }
}

// A validated view of bytes inside one buffer: element i starts at data + i * stride.
struct ByteView {
  const unsigned char* data = nullptr;
  uint64_t stride = 0;
};

// Checks that `count` elements of `elementBytes` at `byteOffset` (with the view's stride,
// or tightly packed) lie inside buffer view `viewIndex`, which lies inside its buffer.
std::string checkView(const tinygltf::Model& model, int viewIndex, uint64_t byteOffset, uint64_t count,
                      uint64_t elementBytes, bool allowStride, ByteView& out) {
  if (viewIndex < 0 || size_t(viewIndex) >= model.bufferViews.size())
    return "bufferView " + std::to_string(viewIndex) + " does not exist (the file has " +
           std::to_string(model.bufferViews.size()) + ")";
  const tinygltf::BufferView& view = model.bufferViews[size_t(viewIndex)];
  const std::string viewName = "bufferView " + std::to_string(viewIndex);
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    return viewName + " refers to buffer " + std::to_string(view.buffer) + ", which does not exist";
  const uint64_t bufferBytes = model.buffers[size_t(view.buffer)].data.size();
  const uint64_t viewOffset = view.byteOffset, viewBytes = view.byteLength;
  if (viewOffset > bufferBytes || viewBytes > bufferBytes - viewOffset)
    return viewName + " covers bytes [" + std::to_string(viewOffset) + ", " + std::to_string(viewOffset + viewBytes) +
           ") but buffer " + std::to_string(view.buffer) + " has only " + std::to_string(bufferBytes) + " bytes";
  uint64_t stride = elementBytes;
  if (view.byteStride != 0) {
    if (!allowStride) return viewName + " has a byteStride, which is not allowed here";
    if (view.byteStride < elementBytes || view.byteStride > 252)
      return viewName + " has byteStride " + std::to_string(view.byteStride) + ", outside [" +
             std::to_string(elementBytes) + ", 252]";
    stride = view.byteStride;
  }
  if (count == 0) return "count is 0";
  // Last element's end; count and stride are bounded (buffers are < 4 GiB), so no overflow
  // once count <= view bytes has been checked.
  if (count > viewBytes || byteOffset > viewBytes ||
      (count - 1) * stride + elementBytes > viewBytes - byteOffset)
    return std::to_string(count) + " elements of " + std::to_string(elementBytes) + " bytes (stride " +
           std::to_string(stride) + ") at byteOffset " + std::to_string(byteOffset) + " do not fit in " + viewName +
           " of " + std::to_string(viewBytes) + " bytes";
  out.data = model.buffers[size_t(view.buffer)].data.data() + viewOffset + byteOffset;
  out.stride = stride;
  return "";
}

// Reads the accessor into doubles (exact for every component type we accept).
std::string readAccessor(const tinygltf::Model& model, int index, int type, unsigned allowed,
                         std::vector<double>& out) {
  if (index < 0 || size_t(index) >= model.accessors.size())
    return "accessor " + std::to_string(index) + " does not exist (the file has " +
           std::to_string(model.accessors.size()) + ")";
  const tinygltf::Accessor& acc = model.accessors[size_t(index)];
  const std::string name = "accessor " + std::to_string(index);
  if (acc.type != type)
    return name + " has type " + typeName(acc.type) + ", expected " + typeName(type);
  if (!componentAllowed(acc.componentType, acc.normalized, allowed))
    return name + " has componentType " + std::to_string(acc.componentType) +
           (acc.normalized ? " (normalized)" : "") + ", which is not allowed for this attribute";
  const uint64_t components = uint64_t(componentCount(type));
  const uint64_t compBytes = uint64_t(componentBytes(acc.componentType));
  const uint64_t count = acc.count;
  if (count == 0) return name + " has count 0";

  out.clear();
  if (acc.bufferView < -1) return name + " has bufferView " + std::to_string(acc.bufferView) + ", not an index";
  if (acc.bufferView >= 0) {
    ByteView bytes;
    std::string err = checkView(model, acc.bufferView, acc.byteOffset, count, components * compBytes, true, bytes);
    if (!err.empty()) return name + ": " + err;
    out.resize(count * components);
    for (uint64_t i = 0; i < count; ++i)
      for (uint64_t c = 0; c < components; ++c)
        out[i * components + c] =
            decodeComponent(bytes.data + i * bytes.stride + c * compBytes, acc.componentType, acc.normalized);
  } else {
    if (count > kMaxUnbackedElements)
      return name + " has no bufferView and an implausible count " + std::to_string(count);
    out.assign(count * components, 0.0);  // glTF: no bufferView means zeros (before sparse)
  }

  if (acc.sparse.isSparse) {
    const auto& sparse = acc.sparse;
    if (sparse.count <= 0 || uint64_t(sparse.count) > count)
      return name + ": sparse count " + std::to_string(sparse.count) + " is outside [1, " + std::to_string(count) + "]";
    const int indexType = sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return name + ": sparse indices have componentType " + std::to_string(indexType) + ", expected an unsigned integer";
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) return name + ": negative sparse byteOffset";
    ByteView indexBytes, valueBytes;
    std::string err = checkView(model, sparse.indices.bufferView, uint64_t(sparse.indices.byteOffset),
                                uint64_t(sparse.count), uint64_t(componentBytes(indexType)), false, indexBytes);
    if (!err.empty()) return name + ": sparse indices: " + err;
    err = checkView(model, sparse.values.bufferView, uint64_t(sparse.values.byteOffset), uint64_t(sparse.count),
                    components * compBytes, false, valueBytes);
    if (!err.empty()) return name + ": sparse values: " + err;
    for (uint64_t k = 0; k < uint64_t(sparse.count); ++k) {
      const double target = decodeComponent(indexBytes.data + k * indexBytes.stride, indexType, false);
      if (target >= double(count))
        return name + ": sparse index " + std::to_string(uint64_t(target)) + " >= count " + std::to_string(count);
      for (uint64_t c = 0; c < components; ++c)
        out[uint64_t(target) * components + c] =
            decodeComponent(valueBytes.data + k * valueBytes.stride + c * compBytes, acc.componentType, acc.normalized);
    }
  }
  return "";
}

}  // namespace

std::string readFloatAccessor(const tinygltf::Model& model, int index, int type, unsigned allowedComponents,
                              std::vector<float>& out) {
  std::vector<double> values;
  std::string err = readAccessor(model, index, type, allowedComponents, values);
  if (!err.empty()) return err;
  out.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      return "accessor " + std::to_string(index) + " holds a non-finite value at element " +
             std::to_string(i / size_t(componentCount(type)));
    out[i] = float(values[i]);
  }
  return "";
}

std::string readIndexAccessor(const tinygltf::Model& model, int index, std::vector<uint32_t>& out) {
  std::vector<double> values;
  std::string err = readAccessor(model, index, TINYGLTF_TYPE_SCALAR, kUnsignedIntegers, values);
  if (!err.empty()) return err;
  out.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) out[i] = uint32_t(values[i]);
  return "";
}

}  // namespace tex::render
