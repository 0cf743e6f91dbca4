#include "compiler/small_domain_tables.h"

#include <llvm/ADT/DenseMap.h>
#include <llvm/ADT/PostOrderIterator.h>
#include <llvm/Analysis/ConstantFolding.h>
#include <llvm/Analysis/ValueTracking.h>
#include <llvm/IR/Constants.h>
#include <llvm/IR/Dominators.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Instructions.h>
#include <llvm/IR/Module.h>
#include <llvm/Support/KnownBits.h>
#include <llvm/Transforms/Utils/Local.h>

#include <map>
#include <vector>

namespace tex::compiler {
namespace {

constexpr unsigned kMaxIndexBits = 6;     // tables of at most 64 entries
constexpr size_t kMaxSliceSize = 64;      // instructions folded per entry

// A phi that chooses between two values by one branch condition: the merge of an if-expression
// the optimiser left as branches (SimplifyCFG speculates only small arms). It is a select.
struct TwoWayPhi {
  llvm::Value* condition = nullptr;
  llvm::Value* ifTrue = nullptr;
  llvm::Value* ifFalse = nullptr;
};

bool matchTwoWayPhi(llvm::PHINode* phi, const llvm::DominatorTree& dominators, TwoWayPhi& match) {
  if (phi->getNumIncomingValues() != 2) return false;
  llvm::BasicBlock* merge = phi->getParent();
  llvm::DomTreeNode* node = dominators.getNode(merge);
  if (!node || !node->getIDom()) return false;
  llvm::BasicBlock* split = node->getIDom()->getBlock();
  auto* branch = llvm::dyn_cast<llvm::BranchInst>(split->getTerminator());
  if (!branch || !branch->isConditional() || branch->getSuccessor(0) == branch->getSuccessor(1)) return false;
  // Which side of the branch an incoming edge comes from: the edge split -> merge itself, or a
  // block only reached through that side's successor. A successor entered from elsewhere too
  // (the other side flowing into it) would make the side ambiguous: refused.
  for (unsigned s = 0; s < 2; ++s) {
    llvm::BasicBlock* successor = branch->getSuccessor(s);
    if (successor != merge && successor->getSinglePredecessor() != split) return false;
  }
  auto side = [&](llvm::BasicBlock* from, int s) {
    llvm::BasicBlock* successor = branch->getSuccessor(unsigned(s));
    return from == split ? successor == merge : dominators.dominates(successor, from) && successor != merge;
  };
  llvm::BasicBlock* a = phi->getIncomingBlock(0);
  llvm::BasicBlock* b = phi->getIncomingBlock(1);
  if (side(a, 0) && side(b, 1)) {
    match = {branch->getCondition(), phi->getIncomingValue(0), phi->getIncomingValue(1)};
    return true;
  }
  if (side(a, 1) && side(b, 0)) {
    match = {branch->getCondition(), phi->getIncomingValue(1), phi->getIncomingValue(0)};
    return true;
  }
  return false;
}

// The instructions a table may replace: pure scalar arithmetic the constant folder evaluates.
bool foldableArithmetic(const llvm::Instruction& inst) {
  if (inst.getType()->isVectorTy()) return false;
  if (!(llvm::isa<llvm::BinaryOperator>(inst) || llvm::isa<llvm::UnaryOperator>(inst) || llvm::isa<llvm::CastInst>(inst) ||
        llvm::isa<llvm::CmpInst>(inst) || llvm::isa<llvm::SelectInst>(inst)))
    return false;
  for (const llvm::Value* op : inst.operands())
    if (op->getType()->isVectorTy()) return false;
  return true;
}

// The values a leaf can take by its known bits: one | (index << shift), index < 2^bits.
struct Domain {
  llvm::APInt one;
  unsigned shift = 0, bits = 0;
  bool needsMask = false;  // bits above the index are known ones
};

bool smallDomain(llvm::Instruction* leaf, const llvm::DataLayout& layout, Domain& domain) {
  if (!leaf->getType()->isIntegerTy() || leaf->getType()->getIntegerBitWidth() > 64) return false;
  llvm::KnownBits known = llvm::computeKnownBits(leaf, layout);
  // A remainder by a positive constant C of a non-negative number is below C (known bits
  // alone only bound it by the dividend).
  auto* divisor = llvm::dyn_cast<llvm::ConstantInt>(leaf->getOperand(leaf->getNumOperands() - 1));
  if ((leaf->getOpcode() == llvm::Instruction::URem || leaf->getOpcode() == llvm::Instruction::SRem) && divisor &&
      divisor->getValue().isStrictlyPositive() &&
      (leaf->getOpcode() == llvm::Instruction::URem ||
       llvm::computeKnownBits(leaf->getOperand(0), layout).isNonNegative())) {
    unsigned width = known.getBitWidth();
    unsigned used = (divisor->getValue() - 1).getActiveBits();
    known.Zero |= llvm::APInt::getHighBitsSet(width, width - used);
    known.One &= ~known.Zero;
  }
  llvm::APInt unknown = ~(known.Zero | known.One);
  unsigned bits = unknown.popcount();
  if (bits == 0 || bits > kMaxIndexBits) return false;
  unsigned shift = unknown.countr_zero();
  if (unknown.lshr(shift).countr_one() != bits) return false;  // not a contiguous field
  domain.one = known.One;
  domain.shift = shift;
  domain.bits = bits;
  domain.needsMask = !known.One.lshr(shift + bits).isZero();
  return true;
}

// What a value depends on: nothing but constants, exactly one non-foldable value (its leaf),
// or several.
llvm::Value* const kSeveral = reinterpret_cast<llvm::Value*>(uintptr_t(1));

struct Slices {
  llvm::DenseMap<const llvm::Value*, llvm::Value*> leaf;  // nullptr: constants only
  llvm::DenseMap<const llvm::Value*, bool> selects;       // a choice somewhere in the slice
  llvm::DenseMap<const llvm::Value*, Domain> domains;     // the leaves of small domain
  llvm::DenseMap<const llvm::Value*, TwoWayPhi> phis;     // the phis that are selects

  llvm::Value* leafOf(llvm::Value* v) const {
    if (llvm::isa<llvm::Constant>(v)) return nullptr;
    auto it = leaf.find(v);
    return it == leaf.end() ? v : it->second;  // not foldable: the value is its own leaf
  }
  bool hasSelect(const llvm::Value* v) const {
    auto it = selects.find(v);
    return it != selects.end() && it->second;
  }

  void analyse(llvm::Function& fn, const llvm::DominatorTree& dominators, const llvm::DataLayout& layout) {
    // Reverse post-order: every operand of a foldable instruction is seen before it (a
    // two-way phi's values come from blocks its split dominates, its condition from the split).
    llvm::ReversePostOrderTraversal<llvm::Function*> order(&fn);
    for (llvm::BasicBlock* block : order)
      for (llvm::Instruction& inst : *block) {
        std::vector<llvm::Value*> operands;
        bool choice = false;
        TwoWayPhi phi;
        if (auto* p = llvm::dyn_cast<llvm::PHINode>(&inst)) {
          if (p->getType()->isVectorTy() || !matchTwoWayPhi(p, dominators, phi)) continue;
          phis[&inst] = phi;
          operands = {phi.condition, phi.ifTrue, phi.ifFalse};
          choice = true;
        } else if (foldableArithmetic(inst)) {
          operands.assign(inst.op_begin(), inst.op_end());
          choice = llvm::isa<llvm::SelectInst>(inst);
        } else {
          continue;
        }
        llvm::Value* common = nullptr;
        for (llvm::Value* op : operands) {
          llvm::Value* l = leafOf(op);
          if (l && common && l != common) common = kSeveral;
          else if (l && !common) common = l;
          choice = choice || hasSelect(op);
        }
        // An integer narrowed to a few bits (`h & 15`, `x % 12`) starts a slice of its own,
        // unless it already is a function of such a leaf. Known bits are only asked of the
        // narrowing operations: they recurse through the operands (integer hashes are long).
        Domain domain;
        unsigned opcode = inst.getOpcode();
        bool narrowing = opcode == llvm::Instruction::And || opcode == llvm::Instruction::LShr ||
                         opcode == llvm::Instruction::URem || opcode == llvm::Instruction::SRem;
        if (narrowing && !(common && common != kSeveral && domains.count(common)) && smallDomain(&inst, layout, domain)) {
          domains[&inst] = domain;
          leaf[&inst] = &inst;
          selects[&inst] = false;
          continue;
        }
        leaf[&inst] = common;
        selects[&inst] = choice;
      }
  }
};

// Folds the slice of a root with its leaf set to one value; nullptr when some instruction on
// the way does not fold to a defined constant. Choices fold their condition first and then
// only the chosen side, as the program would run.
struct SliceFolder {
  const Slices& slices;
  const llvm::DataLayout& layout;
  llvm::Value* leaf;
  llvm::Constant* leafValue;
  llvm::DenseMap<llvm::Value*, llvm::Constant*> folded;

  SliceFolder(const Slices& slices, const llvm::DataLayout& layout, llvm::Value* leaf, llvm::Constant* leafValue)
      : slices(slices), layout(layout), leaf(leaf), leafValue(leafValue) {}

  llvm::Constant* choose(llvm::Value* condition, llvm::Value* ifTrue, llvm::Value* ifFalse) {
    llvm::Constant* c = fold(condition);
    if (!c || !llvm::isa<llvm::ConstantInt>(c)) return nullptr;
    return fold(llvm::cast<llvm::ConstantInt>(c)->isOne() ? ifTrue : ifFalse);
  }

  llvm::Constant* fold(llvm::Value* v) {
    if (v == leaf) return leafValue;
    if (auto* c = llvm::dyn_cast<llvm::Constant>(v)) return c;
    if (auto it = folded.find(v); it != folded.end()) return it->second;
    if (folded.size() >= kMaxSliceSize) return nullptr;
    auto* inst = llvm::cast<llvm::Instruction>(v);  // in the slice: foldable by construction
    llvm::Constant* result = nullptr;
    if (auto it = slices.phis.find(inst); it != slices.phis.end()) {
      result = choose(it->second.condition, it->second.ifTrue, it->second.ifFalse);
    } else if (auto* select = llvm::dyn_cast<llvm::SelectInst>(inst)) {
      result = choose(select->getCondition(), select->getTrueValue(), select->getFalseValue());
    } else {
      std::vector<llvm::Constant*> ops;
      for (llvm::Value* op : inst->operands()) {
        llvm::Constant* c = fold(op);
        if (!c) return nullptr;
        ops.push_back(c);
      }
      if (auto* cmp = llvm::dyn_cast<llvm::CmpInst>(inst))
        result = llvm::ConstantFoldCompareInstOperands(cmp->getPredicate(), ops[0], ops[1], layout);
      else
        result = llvm::ConstantFoldInstOperands(inst, ops, layout);
    }
    if (!result || llvm::isa<llvm::UndefValue>(result) || llvm::isa<llvm::ConstantExpr>(result)) return nullptr;
    folded[v] = result;
    return result;
  }
};

llvm::Constant* tabulate(const Slices& slices, llvm::Instruction* root, llvm::Value* leaf, const Domain& domain,
                         const llvm::DataLayout& layout) {
  std::vector<llvm::Constant*> entries;
  unsigned width = leaf->getType()->getIntegerBitWidth();
  for (uint64_t index = 0; index < (uint64_t(1) << domain.bits); ++index) {
    llvm::APInt value = domain.one | (llvm::APInt(width, index) << domain.shift);
    SliceFolder folder(slices, layout, leaf, llvm::ConstantInt::get(leaf->getType(), value));
    llvm::Constant* entry = folder.fold(root);
    if (!entry) return nullptr;
    entries.push_back(entry);
  }
  return llvm::ConstantArray::get(llvm::ArrayType::get(root->getType(), entries.size()), entries);
}

struct Replacement {
  llvm::Instruction* root;
  llvm::Value* leaf;
  Domain domain;
  llvm::Constant* table;
};

// After the phis of if-expressions became table reads, their branches choose between empty
// blocks: branch straight to the merge block instead (inner ifs first, until nothing changes).
void removeEmptyDiamonds(llvm::Function& fn) {
  for (bool changed = true; changed;) {
    changed = false;
    for (llvm::BasicBlock& block : fn) {
      auto* branch = llvm::dyn_cast<llvm::BranchInst>(block.getTerminator());
      if (!branch || !branch->isConditional()) continue;
      llvm::BasicBlock* ends[2];
      std::vector<llvm::BasicBlock*> forwarders;
      for (unsigned s = 0; s < 2; ++s) {
        llvm::BasicBlock* x = branch->getSuccessor(s);
        while (x != &block && x->size() == 1 && x->getSinglePredecessor() && x->getSingleSuccessor() &&
               forwarders.size() < 64) {
          forwarders.push_back(x);
          x = x->getSingleSuccessor();
        }
        ends[s] = x;
      }
      if (ends[0] != ends[1] || ends[0] == &block || !ends[0]->phis().empty()) continue;
      llvm::Value* condition = branch->getCondition();
      llvm::BranchInst::Create(ends[0], branch);
      branch->eraseFromParent();
      for (llvm::BasicBlock* forwarder : forwarders) forwarder->eraseFromParent();
      llvm::RecursivelyDeleteTriviallyDeadInstructions(condition);
      changed = true;
      break;
    }
  }
}

}  // namespace

size_t tabulateSmallDomainFunctions(llvm::Module& module) {
  const llvm::DataLayout& layout = module.getDataLayout();
  std::map<llvm::Constant*, llvm::GlobalVariable*> globals;  // identical tables shared
  size_t count = 0;
  for (llvm::Function& fn : module) {
    if (fn.isDeclaration()) continue;
    llvm::DominatorTree dominators(fn);
    Slices slices;
    slices.analyse(fn, dominators, layout);
    std::vector<Replacement> replacements;
    for (llvm::BasicBlock& block : fn)
      for (llvm::Instruction& inst : block) {
        llvm::Type* type = inst.getType();
        if (!(type->isFloatTy() || type->isDoubleTy() || (type->isIntegerTy() && !type->isIntegerTy(1)))) continue;
        auto it = slices.leaf.find(&inst);
        if (it == slices.leaf.end() || !it->second || it->second == kSeveral || it->second == &inst ||
            !slices.hasSelect(&inst))
          continue;
        llvm::Value* leaf = it->second;
        // Only the largest such computation: some user must depend on more than the leaf.
        bool largest = false;
        for (llvm::User* user : inst.users()) largest = largest || slices.leafOf(user) != leaf;
        if (!largest) continue;
        auto domain = slices.domains.find(leaf);
        if (domain == slices.domains.end()) continue;
        // The table is read where the root is (after a merge block's phis): the leaf must be
        // available there, which a value computed inside one arm of an if is not.
        llvm::Instruction* readAt = llvm::isa<llvm::PHINode>(inst) ? &*block.getFirstInsertionPt() : &inst;
        if (!dominators.dominates(llvm::cast<llvm::Instruction>(leaf), readAt)) continue;
        if (llvm::Constant* table = tabulate(slices, &inst, leaf, domain->second, layout))
          replacements.push_back({&inst, leaf, domain->second, table});
      }
    if (replacements.empty()) continue;
    // Rewrite only after every table is folded: slices may share instructions.
    llvm::SmallVector<llvm::WeakTrackingVH, 16> dead;
    bool phiReplaced = false;
    for (const Replacement& r : replacements) {
      llvm::GlobalVariable*& global = globals[r.table];
      if (!global) {
        global = new llvm::GlobalVariable(module, r.table->getType(), /*isConstant=*/true, llvm::GlobalValue::PrivateLinkage,
                                          r.table, "tex.table");
        global->setUnnamedAddr(llvm::GlobalValue::UnnamedAddr::Global);
        global->setAlignment(llvm::Align(16));
      }
      phiReplaced = phiReplaced || llvm::isa<llvm::PHINode>(r.root);
      llvm::IRBuilder<> b(r.root->getParent(), r.root->getParent()->getFirstInsertionPt());
      if (!llvm::isa<llvm::PHINode>(r.root)) b.SetInsertPoint(r.root);
      llvm::Value* index = r.leaf;
      if (r.domain.shift) index = b.CreateLShr(index, r.domain.shift);
      if (r.domain.needsMask) index = b.CreateAnd(index, (uint64_t(1) << r.domain.bits) - 1);
      index = b.CreateZExtOrTrunc(index, b.getInt64Ty());
      llvm::Value* slot = b.CreateInBoundsGEP(r.table->getType(), global, {b.getInt64(0), index});
      llvm::Value* entry = b.CreateLoad(r.root->getType(), slot, r.root->getName() + ".tab");
      r.root->replaceAllUsesWith(entry);
      dead.push_back(r.root);
    }
    llvm::RecursivelyDeleteTriviallyDeadInstructionsPermissive(dead);
    if (phiReplaced) removeEmptyDiamonds(fn);
    count += replacements.size();
  }
  return count;
}

}  // namespace tex::compiler
