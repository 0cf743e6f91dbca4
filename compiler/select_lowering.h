// Internal to compiler/: rewrites scalar float selects as integer selects on the bit pattern.
// x86 has no conditional move for SSE registers: a float select whose condition is not a
// float compare becomes a branch (or an AVX-512 mask move), and texture conditions depend on
// hashed bits, so those branches are mispredicted half the time. An integer select becomes a
// `cmov`. Bit-exact: the chosen value is moved, not computed.
#pragma once
#include <llvm/IR/Module.h>

namespace tex::compiler {

void lowerFloatSelectsToIntegerSelects(llvm::Module& module);

}  // namespace tex::compiler
