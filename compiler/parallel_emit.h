// Internal to compiler/: code generation of one optimised module on two threads. Instruction
// selection dominates compile time and works function by function, so the module's functions
// are split into two groups of about equal instruction count (longest first, each to the
// lighter group); one group is emitted here, the other on a TBB worker from a bitcode copy in
// its own LLVMContext. Both objects are linked into the same JITDylib, where calls across the
// groups resolve (every defined function is made external for that).
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace llvm {
class Module;
}

namespace tex::compiler {

// Emits `module` to object code with the calling thread's target machine.
using EmitObjectFn = std::function<bool(llvm::Module& module, std::string& object, std::string& error)>;

// Below this many instructions in the smaller group, splitting costs more than it saves
// (the bitcode copy and the hand-off to the worker take about half a millisecond).
constexpr size_t kMinInstructionsPerPart = 150;

// Fills `objects` with one object, or two when the module splits well. Modifies `module`.
bool emitInParts(llvm::Module& module, const EmitObjectFn& emit, std::vector<std::string>& objects, std::string& error);

}  // namespace tex::compiler
