// Functions compiled code calls back into: building the Material closure tree in the
// caller's arena (docs/abi.md, "Materials"), and image lookups (docs/abi.md, "Images").
#include <atomic>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "compiler/abi.h"
#include "compiler/codegen.h"
#include "lang/image_table.h"
#include "lang/rgb_upsampling.h"

namespace tex::compiler {

// The caller's node is a word array its code has just written with 4-byte stores over a
// memset (docs/abi.md): a load spanning several of those stores cannot be forwarded from the
// store buffer and waits for them to reach the cache, so the node is read a word at a time
// (volatile keeps the compiler from widening the loads). All loads come before the stores:
// interleaved, a load could falsely depend on the store before it whenever the two addresses
// agree modulo 4 KiB (the stack buffer against the arena slot), which depends on the layout.
extern "C" int32_t tex_rt_closure_append(const void* rawCtx, const void* node) {
  const auto* ctx = static_cast<const ShadingContext*>(rawCtx);
  if (!ctx || !ctx->arena) return -1;
  ClosureArena* arena = ctx->arena;
  if (arena->count >= arena->capacity) {
    arena->overflow = 1;
    return -1;
  }
  constexpr size_t kWords = sizeof(ClosureNode) / 4;
  const volatile uint32_t* from = static_cast<const volatile uint32_t*>(node);
  char* to = reinterpret_cast<char*>(&arena->nodes[arena->count]);
#if defined(__SSE2__)
  static_assert(kWords == 27, "6 quads and 3 words");
  const auto word = [&](size_t i) { return _mm_cvtsi32_si128(int(from[i])); };
  const auto quad = [&](size_t i) {
    return _mm_unpacklo_epi64(_mm_unpacklo_epi32(word(i), word(i + 1)), _mm_unpacklo_epi32(word(i + 2), word(i + 3)));
  };
  const __m128i q0 = quad(0), q1 = quad(4), q2 = quad(8), q3 = quad(12), q4 = quad(16), q5 = quad(20);
  const __m128i tail01 = _mm_unpacklo_epi32(word(24), word(25));
  const uint32_t tail2 = from[26];
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to), q0);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 16), q1);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 32), q2);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 48), q3);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 64), q4);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(to + 80), q5);
  _mm_storel_epi64(reinterpret_cast<__m128i*>(to + 96), tail01);
  std::memcpy(to + 104, &tail2, 4);
#else
  for (size_t i = 0; i < kWords; ++i) {
    const uint32_t w = from[i];
    std::memcpy(to + 4 * i, &w, 4);
  }
#endif
  return arena->count++;
}

// Handles are process-specific, so compiled (and cached) code names images by path and
// resolves each once per loaded module; threads racing here store the same value.
extern "C" int32_t tex_rt_image_handle(const char* path, int32_t data, int32_t* cache) {
  std::atomic_ref<int32_t> slot(*cache);
  int32_t handle = slot.load(std::memory_order_acquire);
  if (handle >= 0) return handle;
  handle = lang::ImageTable::global().resolve(path, data != 0);
  if (handle >= 0) slot.store(handle, std::memory_order_release);
  return handle;
}

extern "C" void tex_rt_image_lookup(int32_t filter, int32_t handle, int32_t wrap, float u, float v, float dudx,
                                    float dvdx, float dudy, float dvdy, float* out) {
  lang::imageLookup(handle, lang::ImageFilter(filter), wrap, u, v, dudx, dvdx, dudy, dvdy, out);
}

extern "C" void tex_rt_image_size(int32_t handle, float* out) { lang::imageSize(handle, out); }

extern "C" void tex_rt_rgb_spectrum(int32_t use, const float* rgb, const void* rawCtx, float* out) {
  const auto* ctx = static_cast<const ShadingContext*>(rawCtx);
  lang::rgbToSpectrum(lang::RgbUse(use), rgb, ctx->lambdaNm, ctx->wavelengthCount, out);
}

}  // namespace tex::compiler
