// Functions compiled code calls back into: building the Material closure tree in the
// caller's arena (docs/abi.md, "Materials"), and image lookups (docs/abi.md, "Images").
#include <atomic>
#include <cstring>

#include "compiler/abi.h"
#include "compiler/codegen.h"
#include "lang/image_table.h"
#include "lang/rgb_upsampling.h"

namespace tex::compiler {

// The caller's node is a word array its code has just written with 4-byte stores over a
// memset (docs/abi.md): a load spanning several of those stores cannot be forwarded from the
// store buffer and waits for them to reach the cache, so the node is copied a word at a time
// (volatile keeps the compiler from widening the loads), straight into its arena slot.
extern "C" int32_t tex_rt_closure_append(const void* rawCtx, const void* node) {
  const auto* ctx = static_cast<const ShadingContext*>(rawCtx);
  if (!ctx || !ctx->arena) return -1;
  ClosureArena* arena = ctx->arena;
  if (arena->count >= arena->capacity) {
    arena->overflow = 1;
    return -1;
  }
  const volatile uint32_t* from = static_cast<const volatile uint32_t*>(node);
  char* to = reinterpret_cast<char*>(&arena->nodes[arena->count]);
  for (size_t i = 0; i < sizeof(ClosureNode) / 4; ++i) {
    const uint32_t word = from[i];
    std::memcpy(to + 4 * i, &word, 4);
  }
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
