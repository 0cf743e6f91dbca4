#include "cli/texture_evaluator.h"

#include <cstring>

#include "lang/interpreter.h"

namespace tex::cli {

std::unique_ptr<TextureEvaluator> TextureEvaluator::create(const lang::ir::Program& program, int fn, bool interpret,
                                                           const compiler::CompileOptions& options,
                                                           lang::Diagnostics& diags) {
  auto e = std::unique_ptr<TextureEvaluator>(new TextureEvaluator());
  e->program_ = &program;
  e->fn_ = fn;
  e->resultType_ = program.functions[size_t(fn)].resultType;
  if (!interpret) {
    e->module_ = compiler::compile(program, {fn}, options, diags);
    if (!e->module_) return nullptr;
    e->entry_ = e->module_->entry(fn);
  }
  return e;
}

void TextureEvaluator::evaluate(const compiler::HitAbi& hit, const float* lambdaNm, int count, float* out) const {
  if (entry_) {
    compiler::ShadingContext ctx{};
    for (int i = 0; i < count; ++i) ctx.lambdaNm[i] = lambdaNm[i];
    ctx.wavelengthCount = count;
    float result[compiler::kMaxWavelengths] = {};
    entry_(&hit, result, &ctx);
    std::memcpy(out, result, sizeof result);
    return;
  }
  lang::Value h = lang::makeHit(hit.p, hit.n, hit.uv, hit.duvdx[0], hit.duvdy[1]);
  lang::WavelengthGroup group;
  group.count = count;
  for (int i = 0; i < count; ++i) group.lambdaNm[i] = lambdaNm[i];
  lang::Value v = lang::evaluate(*program_, fn_, {h}, group);
  std::memcpy(out, v.f, sizeof(float) * compiler::kMaxWavelengths);
}

}  // namespace tex::cli
