// Internal to compiler/: lowers typed core IR to an LLVM module (one LLVM function per IR
// function, plus one ABI wrapper `tex_entry_<k>` per requested entry).
#pragma once
#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>

#include <memory>
#include <string>
#include <vector>

#include "lang/core_ir.h"

namespace tex::compiler {

struct CodegenOptions {
  int wavelengths = 4;
  bool inlineEverything = true;  // mark internal functions alwaysinline (O1)...
  // ...except those whose inlining would duplicate more than this many IR operations
  // (own size times the extra call sites): they stay calls, which keeps compile time down.
  uint64_t maxDuplicatedNodes = 400;
  uint64_t alwaysInlineSize = 80;  // leaves this small are inlined wherever they are called
  // Without inlineEverything (quick mode), functions at most this big are still generated in
  // place: their call sequence would cost more machine code than their body.
  uint64_t quickInPlaceSize = 20;
  // Entries bigger than this keep their large loops (functions with a fold, at least
  // minOutlinedLoopSize after inlining) out of line, so code generation can run in parts.
  uint64_t outlineLoopsInEntriesAbove = 1200;
  uint64_t minOutlinedLoopSize = 100;
};

std::string entrySymbol(size_t entryIndex);

// Returns null and sets `error` if the program cannot be lowered (an internal error).
std::unique_ptr<llvm::Module> generateModule(llvm::LLVMContext& context, const lang::ir::Program& program,
                                             const std::vector<int>& entries, const CodegenOptions& options,
                                             std::string& error);

// The names of the runtime functions compiled code calls (bound as absolute symbols).
// The handle of image `path` (a canonical path, NUL-terminated; `data` as image_data()) as it was
// when the code was checked (its size and mtime; the latest load if this process has no such
// version), cached in *cache (an int32 initialised to -1, one per image constant of a module).
extern "C" int32_t tex_rt_image_handle(const char* path, int32_t data, int32_t* cache, uint64_t fileBytes,
                                       int64_t mtimeNs);
// An image lookup (lang::imageLookup): `filter` is a lang::ImageFilter; writes RGBA to out[4].
extern "C" void tex_rt_image_lookup(int32_t filter, int32_t handle, int32_t wrap, float u, float v, float dudx,
                                    float dvdx, float dudy, float dvdy, float* out);
// (width, height) of an image to out[2] (lang::imageSize).
extern "C" void tex_rt_image_size(int32_t handle, float* out);
extern "C" void tex_rt_rgb_spectrum(int32_t use, const float* rgb, const void* ctx, float* out);

}  // namespace tex::compiler
