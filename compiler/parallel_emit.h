// Internal to compiler/: optimisation and code generation of one module on two threads.
// Instruction selection dominates compile time and works function by function, so a big
// module is split before optimisation into two groups of about equal size; one group is
// optimised and emitted on the calling thread, the other on a TBB worker from a bitcode copy in
// its own LLVMContext. Groups are made of the functions that survive inlining (the entry
// wrappers and every function not marked alwaysinline), sized with the alwaysinline callees
// they will absorb; those callees are copied into both groups. Both objects are linked into
// the same JITDylib, where calls across the groups resolve.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace llvm {
class Module;
}

namespace tex::compiler {

// Optimises a module (or a part of one) in place on the calling thread.
using OptimiseFn = std::function<void(llvm::Module& module)>;
// Emits a module to object code with the calling thread's target machine.
using EmitObjectFn = std::function<bool(llvm::Module& module, std::string& object, std::string& error)>;

// Below this many (unoptimised) instructions in the smaller group, splitting costs more than it
// saves (the bitcode copy and the hand-off to the worker take about half a millisecond).
constexpr size_t kMinInstructionsPerPart = 150;

struct PartTimes {
  double optimiseMs = 0, emitMs = 0;  // of the calling thread's part
};

// Fills `objects` with one object, or two when the module splits well. Consumes `module`.
bool optimiseAndEmitInParts(llvm::Module& module, const OptimiseFn& optimise, const EmitObjectFn& emit,
                            std::vector<std::string>& objects, PartTimes& times, std::string& error);

}  // namespace tex::compiler
