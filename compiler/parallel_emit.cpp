#include "compiler/parallel_emit.h"

#include <llvm/Bitcode/BitcodeReader.h>
#include <llvm/Bitcode/BitcodeWriter.h>
#include <llvm/IR/Instructions.h>
#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/Error.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/raw_ostream.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <map>

namespace tex::compiler {
namespace {

bool inlined(const llvm::Function& fn) { return fn.hasFnAttribute(llvm::Attribute::AlwaysInline); }

// Instructions of `fn` once its alwaysinline callees are inlined (each call site counts the
// callee's whole size).
size_t sizeAfterInlining(const llvm::Function& fn, std::map<const llvm::Function*, size_t>& memo) {
  if (auto it = memo.find(&fn); it != memo.end()) return it->second;
  memo[&fn] = 0;  // the language has no recursion; this only guards the walk
  size_t n = 0;
  for (const llvm::BasicBlock& block : fn)
    for (const llvm::Instruction& inst : block) {
      ++n;
      if (auto* call = llvm::dyn_cast<llvm::CallInst>(&inst))
        if (const llvm::Function* callee = call->getCalledFunction(); callee && !callee->isDeclaration() && inlined(*callee))
          n += sizeAfterInlining(*callee, memo);
    }
  return memo[&fn] = n;
}

// Group (0 or 1) of each function that survives inlining, by name: longest first, each to the
// lighter group. `sizes` receives the groups' totals.
std::map<std::string, int> balance(const llvm::Module& module, size_t sizes[2]) {
  std::map<const llvm::Function*, size_t> memo;
  std::vector<std::pair<size_t, std::string>> roots;
  for (const llvm::Function& fn : module)
    if (!fn.isDeclaration() && !inlined(fn)) roots.push_back({sizeAfterInlining(fn, memo), fn.getName().str()});
  // Ties by name, so the split is deterministic.
  std::sort(roots.begin(), roots.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::map<std::string, int> group;
  sizes[0] = sizes[1] = 0;
  for (const auto& [size, name] : roots) {
    // The largest root goes to the worker (measured: the calling thread's share then ends
    // with the worker's, as the bitcode copy on one side and its parse on the other cancel).
    int g = sizes[1] <= sizes[0] ? 1 : 0;
    group[name] = g;
    sizes[g] += size;
  }
  return group;
}

// Turns the other group's functions into declarations.
void keepGroup(llvm::Module& module, const std::map<std::string, int>& group, int keep) {
  for (llvm::Function& fn : module) {
    if (fn.isDeclaration()) continue;
    auto it = group.find(fn.getName().str());
    if (it != group.end() && it->second != keep) fn.deleteBody();  // now an external declaration
  }
}

double millisecondsSince(std::chrono::steady_clock::time_point& start) {
  auto now = std::chrono::steady_clock::now();
  double ms = std::chrono::duration<double, std::milli>(now - start).count();
  start = now;
  return ms;
}

}  // namespace

bool optimiseAndEmitInParts(llvm::Module& module, const OptimiseFn& optimise, const EmitObjectFn& emit,
                            std::vector<std::string>& objects, PartTimes& times, std::string& error) {
  objects.clear();
  size_t sizes[2];
  std::map<std::string, int> group = balance(module, sizes);
  auto clock = std::chrono::steady_clock::now();
  if (std::min(sizes[0], sizes[1]) < kMinInstructionsPerPart) {
    optimise(module);
    times.optimiseMs = millisecondsSince(clock);
    objects.emplace_back();
    bool ok = emit(module, objects[0], error);
    times.emitMs = millisecondsSince(clock);
    return ok;
  }
  // Calls may now cross objects: every function of a group must be visible to the other.
  for (llvm::Function& fn : module)
    if (group.count(fn.getName().str()) && fn.hasLocalLinkage()) {
      fn.setLinkage(llvm::GlobalValue::ExternalLinkage);
      fn.setVisibility(llvm::GlobalValue::DefaultVisibility);
    }
  llvm::SmallVector<char, 0> bitcode;
  {
    llvm::raw_svector_ostream out(bitcode);
    llvm::WriteBitcodeToFile(module, out);
  }
  objects.resize(2);
  std::string workerError;
  bool workerOk = false;
  tbb::task_group worker;
  worker.run([&] {
    llvm::LLVMContext context;  // one per thread: LLVM contexts are not shared across threads
    llvm::MemoryBufferRef buffer(llvm::StringRef(bitcode.data(), bitcode.size()), "tex");
    auto parsed = llvm::parseBitcodeFile(buffer, context);
    if (!parsed) {
      workerError = "bitcode round trip: " + llvm::toString(parsed.takeError());
      return;
    }
    keepGroup(**parsed, group, 1);
    optimise(**parsed);
    workerOk = emit(**parsed, objects[1], workerError);
  });
  keepGroup(module, group, 0);
  optimise(module);
  times.optimiseMs = millisecondsSince(clock);
  bool ok = emit(module, objects[0], error);
  times.emitMs = millisecondsSince(clock);
  worker.wait();
  if (ok && !workerOk) {
    error = workerError;
    ok = false;
  }
  return ok;
}

}  // namespace tex::compiler
