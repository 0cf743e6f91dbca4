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
  uint64_t alwaysInlineSize = 64;  // leaves this small are inlined wherever they are called
};

std::string entrySymbol(size_t entryIndex);

// Returns null and sets `error` if the program cannot be lowered (an internal error).
std::unique_ptr<llvm::Module> generateModule(llvm::LLVMContext& context, const lang::ir::Program& program,
                                             const std::vector<int>& entries, const CodegenOptions& options,
                                             std::string& error);

// The names of the runtime functions compiled code calls (bound as absolute symbols).
// A material leaf: kind, flags, then up to two parameter vectors (params2 may be null).
extern "C" int32_t tex_rt_closure_leaf(const void* ctx, uint32_t kind, uint32_t flags, uint32_t paramKind,
                                       const float* params, int32_t count, uint32_t param2Kind, const float* params2,
                                       int32_t count2);
extern "C" int32_t tex_rt_closure_mix(const void* ctx, int32_t a, int32_t b, float weight);

}  // namespace tex::compiler
