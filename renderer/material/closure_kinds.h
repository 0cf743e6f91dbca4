// Which material primitives a function may build: a scan of its body and of every function it
// calls or folds with (lang/core_ir.h). Lets the renderer know before rendering whether a
// material can ever produce, say, a thin wall that straight rays pass.
#pragma once
#include "lang/core_ir.h"

namespace tex::render {

bool mayBuildPrimitive(const lang::ir::Program& program, int function, lang::ir::Prim prim);

}  // namespace tex::render
