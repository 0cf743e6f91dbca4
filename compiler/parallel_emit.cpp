#include "compiler/parallel_emit.h"

#include <llvm/Bitcode/BitcodeReader.h>
#include <llvm/Bitcode/BitcodeWriter.h>
#include <llvm/IR/LLVMContext.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/Error.h>
#include <llvm/Support/MemoryBuffer.h>
#include <llvm/Support/raw_ostream.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <map>

namespace tex::compiler {
namespace {

size_t instructionCount(const llvm::Function& fn) {
  size_t n = 0;
  for (const llvm::BasicBlock& block : fn) n += block.size();
  return n;
}

// Group (0 or 1) of each defined function, by name; `sizes` receives the groups' totals.
std::map<std::string, int> balance(const llvm::Module& module, size_t sizes[2]) {
  std::vector<std::pair<size_t, std::string>> functions;
  for (const llvm::Function& fn : module)
    if (!fn.isDeclaration()) functions.push_back({instructionCount(fn), fn.getName().str()});
  // Largest first; ties by name, so the split is deterministic.
  std::sort(functions.begin(), functions.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  std::map<std::string, int> group;
  sizes[0] = sizes[1] = 0;
  for (const auto& [size, name] : functions) {
    int g = sizes[1] < sizes[0] ? 1 : 0;
    group[name] = g;
    sizes[g] += size;
  }
  return group;
}

// Turns the functions of the other group into declarations.
void keepGroup(llvm::Module& module, const std::map<std::string, int>& group, int keep) {
  for (llvm::Function& fn : module) {
    if (fn.isDeclaration()) continue;
    auto it = group.find(fn.getName().str());
    if (it != group.end() && it->second != keep) fn.deleteBody();  // now an external declaration
  }
}

}  // namespace

bool emitInParts(llvm::Module& module, const EmitObjectFn& emit, std::vector<std::string>& objects, std::string& error) {
  objects.clear();
  size_t sizes[2];
  std::map<std::string, int> group = balance(module, sizes);
  if (std::min(sizes[0], sizes[1]) < kMinInstructionsPerPart) {
    objects.emplace_back();
    return emit(module, objects[0], error);
  }
  // Calls may now cross objects: every definition must be visible to the other one.
  for (llvm::Function& fn : module)
    if (!fn.isDeclaration() && fn.hasLocalLinkage()) {
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
    auto parsed = llvm::parseBitcodeFile(llvm::MemoryBufferRef(llvm::StringRef(bitcode.data(), bitcode.size()), "tex"), context);
    if (!parsed) {
      workerError = "bitcode round trip: " + llvm::toString(parsed.takeError());
      return;
    }
    keepGroup(**parsed, group, 1);
    workerOk = emit(**parsed, objects[1], workerError);
  });
  keepGroup(module, group, 0);
  bool ok = emit(module, objects[0], error);
  worker.wait();
  if (ok && !workerOk) {
    error = workerError;
    ok = false;
  }
  return ok;
}

}  // namespace tex::compiler
