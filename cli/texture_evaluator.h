// Evaluates one texture function (h: Hit) -> T for the CLI, either compiled by the JIT (the
// default) or by the reference interpreter (--interp). Thread-safe: evaluate() may be called
// from many threads at once.
#pragma once
#include <memory>
#include <string>

#include "compiler/abi.h"
#include "compiler/jit.h"
#include "lang/session.h"

namespace tex::cli {

class TextureEvaluator {
 public:
  // Compiles program function `fn` unless `interpret`; on failure returns null with
  // diagnostics in `diags`.
  static std::unique_ptr<TextureEvaluator> create(const lang::ir::Program& program, int fn, bool interpret,
                                                  const compiler::CompileOptions& options, lang::Diagnostics& diags);

  // Writes the result's float lanes (Float 1, VecN N, Color 3, Spectrum `count`) to `out`.
  void evaluate(const compiler::HitAbi& hit, const float* lambdaNm, int count, float* out) const;
  const lang::Type* resultType() const { return resultType_; }
  bool compiled() const { return module_ != nullptr; }
  const compiler::CompiledModule* module() const { return module_.get(); }

 private:
  const lang::ir::Program* program_ = nullptr;
  int fn_ = -1;
  const lang::Type* resultType_ = nullptr;
  std::unique_ptr<compiler::CompiledModule> module_;
  compiler::EntryFn entry_ = nullptr;
};

}  // namespace tex::cli
