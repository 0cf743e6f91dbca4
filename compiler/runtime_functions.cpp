// Functions compiled code calls back into: building the Material closure tree in the
// caller's arena (docs/abi.md, "Materials").
#include <cstring>

#include "compiler/abi.h"
#include "compiler/codegen.h"

namespace tex::compiler {

static int32_t appendNode(const ShadingContext* ctx, const ClosureNode& node) {
  if (!ctx || !ctx->arena) return -1;
  ClosureArena* arena = ctx->arena;
  if (arena->count >= arena->capacity) {
    arena->overflow = 1;
    return -1;
  }
  arena->nodes[arena->count] = node;
  return arena->count++;
}

extern "C" int32_t tex_rt_closure_append(const void* rawCtx, const void* node) {
  ClosureNode copy;
  std::memcpy(&copy, node, sizeof copy);  // the caller's buffer is a word array, not a ClosureNode
  return appendNode(static_cast<const ShadingContext*>(rawCtx), copy);
}

}  // namespace tex::compiler
