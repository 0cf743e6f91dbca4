#pragma once

#include <cstddef>

namespace llvm {
class Module;
}

namespace tex::compiler {

// Replaces a pure computation that depends on a single integer of at most 64 possible values
// (as known bits prove: `h & 15`, `(h >> 8) & 7`) and chooses among values with selects, by
// a read from a constant table of its values: LLVM's switch-to-lookup-table for select trees.
// The language has no arrays; a lattice gradient written as coefficients of the hashed corner
// (std.noise's grad3) thereby compiles as C++ with gradient tables does, instead of compares
// and moves between integer and float registers. Exact: every entry is LLVM's constant fold of
// the very instructions it replaces. Scalar Float and Int results only; run after the IR
// optimiser (it folds the selects' conditions first).
// Returns how many computations became table reads.
size_t tabulateSmallDomainFunctions(llvm::Module& module);

}  // namespace tex::compiler
