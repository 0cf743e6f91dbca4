#include "compiler/select_lowering.h"

#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/InstrTypes.h>
#include <llvm/IR/Instructions.h>

#include <vector>

namespace tex::compiler {

void lowerFloatSelectsToIntegerSelects(llvm::Module& module) {
  std::vector<llvm::SelectInst*> selects;
  for (llvm::Function& fn : module)
    for (llvm::BasicBlock& block : fn)
      for (llvm::Instruction& inst : block)
        if (auto* select = llvm::dyn_cast<llvm::SelectInst>(&inst))
          if (select->getType()->isFloatTy() && !llvm::isa<llvm::FCmpInst>(select->getCondition()))
            selects.push_back(select);
  for (llvm::SelectInst* select : selects) {
    llvm::IRBuilder<> b(select);
    llvm::Type* i32 = b.getInt32Ty();
    // select(c, x, -x) and select(c, -x, x) only choose a sign: flip the sign bit instead.
    llvm::Value* t = select->getTrueValue();
    llvm::Value* f = select->getFalseValue();
    llvm::Value* x = nullptr;
    bool negateWhenTrue = false;
    if (auto* neg = llvm::dyn_cast<llvm::UnaryOperator>(f); neg && neg->getOpcode() == llvm::Instruction::FNeg && neg->getOperand(0) == t)
      x = t;
    else if (auto* neg = llvm::dyn_cast<llvm::UnaryOperator>(t); neg && neg->getOpcode() == llvm::Instruction::FNeg && neg->getOperand(0) == f)
      x = f, negateWhenTrue = true;
    if (x) {
      llvm::Value* flip = b.CreateZExt(negateWhenTrue ? select->getCondition() : b.CreateNot(select->getCondition()), i32);
      llvm::Value* bits = b.CreateXor(b.CreateBitCast(x, i32), b.CreateShl(flip, 31));
      llvm::Value* result = b.CreateBitCast(bits, select->getType());
      result->takeName(select);
      select->replaceAllUsesWith(result);
      select->eraseFromParent();
      continue;
    }
    llvm::Value* bits = b.CreateSelect(select->getCondition(), b.CreateBitCast(select->getTrueValue(), i32),
                                       b.CreateBitCast(select->getFalseValue(), i32));
    llvm::Value* result = b.CreateBitCast(bits, select->getType());
    result->takeName(select);
    select->replaceAllUsesWith(result);
    select->eraseFromParent();
  }
}

}  // namespace tex::compiler
