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

extern "C" int32_t tex_rt_closure_leaf(const void* rawCtx, uint32_t kind, uint32_t paramKind, const float* params,
                                       int32_t count) {
  ClosureNode node{};
  node.kind = ClosureKind(kind);
  node.paramKind = ClosureParam(paramKind);
  node.a = node.b = -1;
  if (count > kMaxWavelengths) count = kMaxWavelengths;
  std::memcpy(node.params, params, sizeof(float) * size_t(count > 0 ? count : 0));
  return appendNode(static_cast<const ShadingContext*>(rawCtx), node);
}

extern "C" int32_t tex_rt_closure_mix(const void* rawCtx, int32_t a, int32_t b, float weight) {
  ClosureNode node{};
  node.kind = ClosureKind::Mix;
  node.paramKind = ClosureParam::None;
  node.a = a;
  node.b = b;
  node.weight = weight;
  return appendNode(static_cast<const ShadingContext*>(rawCtx), node);
}

}  // namespace tex::compiler
