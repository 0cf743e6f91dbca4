#include "renderer/geometry/equal_primitives.h"

#include <cstring>
#include <unordered_map>

#include "renderer/sampling/hash.h"

namespace tex::render {

namespace {

template <class T>
uint64_t hashArray(uint64_t h, const std::vector<T>& values) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  const size_t size = values.size() * sizeof(T);
  h = sampling::hashWords(h, size);
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    uint64_t word;
    std::memcpy(&word, bytes + i, 8);
    h = sampling::hashWords(h, word);
  }
  uint64_t tail = 0;
  if (size > i) std::memcpy(&tail, bytes + i, size - i);  // (never a null source: empty arrays skip it)
  return sampling::hashWords(h, tail);
}

uint64_t hashPrimitive(const MeshPrimitive& p) {
  uint64_t h = hashArray(0, p.positions);
  h = hashArray(h, p.normals);
  h = hashArray(h, p.uv0);
  h = hashArray(h, p.uv1);
  h = hashArray(h, p.tangents);
  h = hashArray(h, p.colors);
  return hashArray(h, p.indices);
}

// Bitwise equality: the same bits give the same geometry (and -0 / NaN never merge wrongly).
template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool sameTriangles(const MeshPrimitive& a, const MeshPrimitive& b) {
  return sameBits(a.indices, b.indices) && sameBits(a.positions, b.positions) && sameBits(a.normals, b.normals) &&
         sameBits(a.uv0, b.uv0) && sameBits(a.uv1, b.uv1) && sameBits(a.tangents, b.tangents) &&
         sameBits(a.colors, b.colors);
}

}  // namespace

std::vector<int> firstEqualPrimitive(const SceneDescription& scene, const std::vector<bool>& eligible) {
  const size_t n = scene.primitives.size();
  std::vector<int> first(n);
  std::unordered_multimap<uint64_t, int> byHash;
  for (size_t p = 0; p < n; ++p) {
    first[p] = int(p);
    const MeshPrimitive& prim = scene.primitives[p];
    if (p >= eligible.size() || !eligible[p] || prim.indices.empty()) continue;
    const uint64_t h = hashPrimitive(prim);
    const auto [begin, end] = byHash.equal_range(h);
    for (auto it = begin; it != end; ++it)
      if (sameTriangles(scene.primitives[size_t(it->second)], prim)) {
        first[p] = it->second;
        break;
      }
    if (first[p] == int(p)) byHash.emplace(h, int(p));
  }
  return first;
}

}  // namespace tex::render
