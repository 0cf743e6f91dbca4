// Internal to compiler/: a canonical text of the functions reachable from some entries,
// independent of where they sit in the program (functions renumbered in discovery order,
// types numbered by first use, constants as bit patterns). Cache keys hash it, and the
// code-size estimate walks the same reachable set.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "lang/core_ir.h"

namespace tex::compiler {

std::string canonicalText(const lang::ir::Program& program, const std::vector<int>& entries);

// IR nodes after inlining every call (folds count their body once): the specialised size.
// Saturates instead of overflowing.
uint64_t inlinedSize(const lang::ir::Program& program, int function);

// The largest value (in 32-bit words, Spectrum counted at `wavelengths` lanes) any node of the
// functions reachable from `function` computes, and its type. Records can share structure
// (`{a: x, b: x}` nested 40 deep is 2^40 words in a type of 41 nodes): sizes are memoised
// per type and saturate.
struct LargestValue {
  uint64_t words = 0;
  const lang::Type* type = nullptr;
};
LargestValue largestValue(const lang::ir::Program& program, int function, int wavelengths);

}  // namespace tex::compiler
