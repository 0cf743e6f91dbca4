// The reference tree-walking interpreter over the typed core IR: the language's semantic
// oracle (docs/language.md section 5). The JIT must agree with it.
#pragma once
#include <vector>

#include "lang/core_ir.h"
#include "lang/value.h"

namespace tex::lang {

// Closure nodes one evaluation may build, as the JIT's arena bounds them (docs/abi.md,
// "Materials"): past the limit, material constructors return no tree (a null material) and
// the evaluation reports the overflow. A fold building millions of nodes had taken gigabytes.
struct ClosureBudget {
  size_t nodeLimit = 65536;
  bool overflowed = false;  // set by evaluate when a material needed more nodes
};

// Evaluates program.functions[function] on the arguments. Pure and re-entrant: call it from
// many threads at once on one program.
Value evaluate(const ir::Program& program, int function, const std::vector<Value>& args,
               const WavelengthGroup& group = {}, ClosureBudget* budget = nullptr);

// A Hit value for uv in the unit square, as `tex eval` and the REPL use it: p = (u, v, 0),
// n = (0, 0, 1), dpdx/dpdy and duvdx/duvdy one pixel's step.
Value makeHit(float u, float v, float du = 0, float dv = 0);
Value makeHit(const float p[3], const float n[3], const float uv[2], float du, float dv);

}  // namespace tex::lang
