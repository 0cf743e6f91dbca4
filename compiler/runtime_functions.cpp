// Functions compiled code calls back into: image lookups (docs/abi.md, "Images") and RGB
// upsampling. (Material nodes are appended to the arena inline: codegen.cpp.)
#include <atomic>

#include "compiler/abi.h"
#include "compiler/codegen.h"
#include "lang/image_table.h"
#include "lang/rgb_upsampling.h"

namespace tex::compiler {

// Handles are process-specific, so compiled (and cached) code names images by path and the
// file's identity when it was checked, and resolves each once per loaded module; threads racing
// here store the same value.
extern "C" int32_t tex_rt_image_handle(const char* path, int32_t data, int32_t* cache, uint64_t fileBytes,
                                       int64_t mtimeNs) {
  std::atomic_ref<int32_t> slot(*cache);
  int32_t handle = slot.load(std::memory_order_acquire);
  if (handle >= 0) return handle;
  handle = lang::ImageTable::global().resolve(path, data != 0, fileBytes, mtimeNs);
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
