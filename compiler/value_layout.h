// Converts between the interpreter's values and the ABI's word layout (docs/abi.md), so the
// interpreter and compiled code can be compared and the REPL can print compiled results.
#pragma once
#include <cstdint>
#include <vector>

#include "compiler/abi.h"
#include "lang/value.h"

namespace tex::compiler {

// Writes `value` of `type` as words; Spectrum has `wavelengths` lanes.
void flatten(const lang::Value& value, const lang::Type* type, int wavelengths, std::vector<uint32_t>& words);
// Reads a value back; Material indices are resolved through `arena` (may be null).
lang::Value unflatten(const uint32_t* words, const lang::Type* type, int wavelengths, const ClosureArena* arena);

}  // namespace tex::compiler
