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

extern "C" int32_t tex_rt_closure_leaf(const void* rawCtx, uint32_t kind, uint32_t flags, uint32_t paramKind,
                                       const float* params, int32_t count, uint32_t param2Kind, const float* params2,
                                       int32_t count2) {
  ClosureNode node{};
  node.kind = ClosureKind(kind);
  node.flags = flags;
  node.paramKind = ClosureParam(paramKind);
  node.param2Kind = ClosureParam(param2Kind);
  node.a = node.b = -1;
  auto copy = [](float* to, const float* from, int32_t n) {
    if (n > kMaxWavelengths) n = kMaxWavelengths;
    if (from && n > 0) std::memcpy(to, from, sizeof(float) * size_t(n));
  };
  copy(node.params, params, count);
  copy(node.params2, params2, count2);
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
