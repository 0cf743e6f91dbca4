#pragma once

namespace llvm {
class Module;
}

namespace tex::compiler {

// Hides the result of every scalar integer multiply from instruction selection behind an
// empty inline-asm copy (no machine code). Integer hashes are chains of multiplies, xors and
// shifts; SelectionDAG's known-bits and demanded-bits analyses recurse through such chains
// (depth 6, both operands of every xor), which made hash-heavy textures spend most of their
// compile time there. Run after the IR optimiser, so IR-level optimisation is unaffected.
void insertIntegerMultiplyBarriers(llvm::Module& module);

}  // namespace tex::compiler
