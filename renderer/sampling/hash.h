// Integer hashing for samplers: every random-looking number in tex is a pure function of
// (seed, sample index, dimension) built from these mixers.
#pragma once
#include <cstdint>

namespace tex::sampling {

// A strong 64-bit finaliser (splitmix64 / Stafford's variant 13).
inline constexpr uint64_t mix64(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ull;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebull;
  x ^= x >> 31;
  return x;
}

// Hashes a sequence of words into one; order matters.
inline constexpr uint64_t hashWords(uint64_t a, uint64_t b) { return mix64(a ^ mix64(b + 0x9e3779b97f4a7c15ull)); }
inline constexpr uint64_t hashWords(uint64_t a, uint64_t b, uint64_t c) { return hashWords(hashWords(a, b), c); }

// lowbias32 (C. Wellons' 32-bit finaliser): the mixer for 32-bit words where 64-bit hashes would
// not vectorise. U: uint32_t or a GCC vector of them.
template <class U>
inline U lowbias32(U x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

// [0,1) float from the top 24 bits of a 32-bit word (exact, never 1.0).
inline constexpr float bitsToUnitFloat(uint32_t bits) { return float(bits >> 8) * 0x1p-24f; }

}  // namespace tex::sampling
