#include "compiler/isel_barriers.h"

#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/InlineAsm.h>
#include <llvm/IR/Instructions.h>
#include <llvm/IR/Module.h>

#include <vector>

namespace tex::compiler {

void insertIntegerMultiplyBarriers(llvm::Module& module) {
  std::vector<llvm::BinaryOperator*> products;
  for (llvm::Function& fn : module)
    for (llvm::BasicBlock& block : fn)
      for (llvm::Instruction& inst : block)
        if (auto* op = llvm::dyn_cast<llvm::BinaryOperator>(&inst))
          if (op->getOpcode() == llvm::Instruction::Mul && op->getType()->isIntegerTy(32)) products.push_back(op);
  if (products.empty()) return;
  llvm::Type* i32 = llvm::Type::getInt32Ty(module.getContext());
  // "=r,0": the output is the input's register; no instruction is emitted.
  llvm::InlineAsm* copy = llvm::InlineAsm::get(llvm::FunctionType::get(i32, {i32}, false), "", "=r,0", false);
  for (llvm::BinaryOperator* product : products) {
    llvm::IRBuilder<> b(product->getNextNode());
    llvm::CallInst* hidden = b.CreateCall(copy, {product});
    // No memory access, no side effect: CSE may merge copies and DCE may drop unused ones.
    hidden->setDoesNotAccessMemory();
    hidden->setDoesNotThrow();
    hidden->addFnAttr(llvm::Attribute::WillReturn);
    product->replaceUsesWithIf(hidden, [hidden](llvm::Use& use) { return use.getUser() != hidden; });
  }
}

}  // namespace tex::compiler
