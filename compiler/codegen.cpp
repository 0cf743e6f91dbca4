// Lowers the typed core IR to LLVM IR (docs/abi.md). Float semantics follow
// docs/language.md section 5: no fast-math flags, no FMA contraction, transcendental
// functions are the C library's (the same the interpreter calls).
#include "compiler/codegen.h"

#include <llvm/IR/BasicBlock.h>
#include <llvm/IR/Constants.h>
#include <llvm/IR/DerivedTypes.h>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Intrinsics.h>
#include <llvm/IR/MDBuilder.h>
#include <llvm/IR/Verifier.h>
#include <llvm/Support/raw_ostream.h>

#include <functional>
#include <map>
#include <unordered_map>
#include <set>

#include "compiler/abi.h"
#include "compiler/canonical_ir.h"
#include "lang/image_table.h"
#include "lang/wavelength_dependence.h"

namespace tex::compiler {

using lang::Type;
using lang::TypeKind;
using lang::ir::Node;
using lang::ir::Prim;

std::string entrySymbol(size_t entryIndex) { return "tex_entry_" + std::to_string(entryIndex); }

namespace {

class Codegen {
 public:
  Codegen(llvm::LLVMContext& c, const lang::ir::Program& p, const CodegenOptions& o)
      : context_(c), program_(p), options_(o), module_(std::make_unique<llvm::Module>("tex", c)), b_(c), dependence_(p) {
    ptrTy_ = llvm::PointerType::get(c, 0);
    f32_ = llvm::Type::getFloatTy(c);
    i32_ = llvm::Type::getInt32Ty(c);
    i1_ = llvm::Type::getInt1Ty(c);
    llvm::MDBuilder md(c);
    unpredictable_ = md.createUnpredictable();
    likely_ = md.createBranchWeights(4096, 1);
  }

  std::unique_ptr<llvm::Module> run(const std::vector<int>& entries, std::string& error) {
    countCallSites(entries);
    planOutlining(entries);
    for (size_t k = 0; k < entries.size(); ++k) {
      int e = entries[k];
      llvm::Function* fn = function(e, dependence_.buildsMaterial(e) ? dependence_.entryContext(e) : -1);
      emitEntry(e, fn, k);
    }
    // Bodies are generated on demand by function(); drain the queue.
    while (!pending_.empty()) {
      FunctionKey key = pending_.back();
      pending_.pop_back();
      emitBody(key);
    }
    std::string message;
    llvm::raw_string_ostream out(message);
    if (llvm::verifyModule(*module_, &out)) {
      error = "internal compiler error: generated LLVM IR is invalid: " + out.str();
      return nullptr;
    }
    return std::move(module_);
  }

 private:
  // ---- types ---------------------------------------------------------------------------
  int lanes(const Type* t) const { return t->kind == TypeKind::Spectrum ? options_.wavelengths : t->fixedLanes(); }

  // Memoised: record types share structure (a type of 41 nodes can have 2^40 leaves, refused by
  // the size check in jit.cpp; still, each distinct type is lowered once).
  llvm::Type* lower(const Type* t) {
    if (auto it = lowered_.find(t); it != lowered_.end()) return it->second;
    llvm::Type* l = lowerUncached(t);
    lowered_[t] = l;
    return l;
  }
  llvm::Type* lowerUncached(const Type* t) {
    switch (t->kind) {
      case TypeKind::Bool: return i1_;
      case TypeKind::Int: return i32_;
      case TypeKind::Material: return i32_;
      case TypeKind::Image: return i32_;
      case TypeKind::Float: return f32_;
      case TypeKind::Vec2:
      case TypeKind::Vec3:
      case TypeKind::Vec4:
      case TypeKind::Color:
      case TypeKind::Spectrum: return llvm::FixedVectorType::get(f32_, unsigned(lanes(t)));
      case TypeKind::Record:
      case TypeKind::Lambda: {
        std::vector<llvm::Type*> fields;
        for (auto& f : t->fields) fields.push_back(lower(f.second));
        return llvm::StructType::get(context_, fields);
      }
      default: return llvm::StructType::get(context_, {});  // FuncRef, BuiltinRef: no data
    }
  }

  // ---- functions -----------------------------------------------------------------------
  // An IR function that builds materials gets one LLVM function per wavelength-dependence
  // context (lang/wavelength_dependence.h), since its closure flags may differ; any other
  // function gets one (context -1).
  using FunctionKey = std::pair<int, int>;  // (IR function, context or -1)

  llvm::Function* function(int index, int context) {
    FunctionKey key{index, context};
    if (auto it = functions_.find(key); it != functions_.end()) return it->second;
    const lang::ir::Function& f = program_.functions[size_t(index)];
    std::vector<llvm::Type*> params = {ptrTy_};
    for (const Type* t : f.paramTypes) params.push_back(lower(t));
    auto* type = llvm::FunctionType::get(lower(f.resultType), params, false);
    std::string name = "f";
    name += std::to_string(index);
    if (context >= 0) name += ".c" + std::to_string(context);
    auto* fn = llvm::Function::Create(type, llvm::Function::InternalLinkage, name, *module_);
    fn->addFnAttr(llvm::Attribute::NoUnwind);
    fn->addFnAttr(llvm::Attribute::WillReturn);
    if (options_.inlineEverything) fn->addFnAttr(inlinedAtCalls(index) ? llvm::Attribute::AlwaysInline : llvm::Attribute::NoInline);
    functions_[key] = fn;
    pending_.push_back(key);
    return fn;
  }

  // Whether calls to function `index` are expanded in place (the body generated at the call
  // site) rather than called: always unless it is outlined or would be duplicated too much.
  // Decided once per function: every call site asks.
  bool inlinedAtCalls(int index) {
    if (outlined_.count(index)) return false;
    if (auto it = inlinedAtCalls_.find(index); it != inlinedAtCalls_.end()) return it->second;
    uint64_t sites = callSites_[index];
    uint64_t size = inlinedSize(program_, index);
    bool inlined = options_.inlineEverything
                       ? sites <= 1 || size <= options_.alwaysInlineSize || size * (sites - 1) <= options_.maxDuplicatedNodes
                       : size <= options_.quickInPlaceSize;
    inlinedAtCalls_[index] = inlined;
    return inlined;
  }

  // The body of the callee of a Call or Fold node generated in place with `args` as its
  // parameters. The language is pure and first order, so this is exactly a call, and cheaper
  // to compile than a call LLVM's inliner expands later.
  llvm::Value* genInPlace(const Node* n, const std::vector<llvm::Value*>& args) {
    bool contextual = dependenceContext_ >= 0 && dependence_.buildsMaterial(n->callee);
    int context = contextual ? dependence_.calleeContext(dependenceContext_, n) : -1;
    const lang::ir::Function& f = program_.functions[size_t(n->callee)];
    std::vector<llvm::Value*> callerSlots(size_t(std::max<int>(f.numSlots, int(f.paramTypes.size()))), nullptr);
    std::swap(slots_, callerSlots);
    for (size_t i = 0; i < args.size() && i < slots_.size(); ++i) slots_[i] = args[i];
    int callerContext = dependenceContext_;
    dependenceContext_ = context;
    llvm::Value* result = gen(f.body);
    dependenceContext_ = callerContext;
    std::swap(slots_, callerSlots);
    return result;
  }

  // The callee of a Call or Fold node in the function being emitted.
  llvm::Function* callee(const Node* n) {
    bool contextual = dependenceContext_ >= 0 && dependence_.buildsMaterial(n->callee);
    return function(n->callee, contextual ? dependence_.calleeContext(dependenceContext_, n) : -1);
  }

  void emitBody(FunctionKey key) {
    const lang::ir::Function& f = program_.functions[size_t(key.first)];
    llvm::Function* fn = functions_[key];
    dependenceContext_ = key.second;
    auto* entry = llvm::BasicBlock::Create(context_, "entry", fn);
    b_.SetInsertPoint(entry);
    ctx_ = fn->getArg(0);
    slots_.assign(size_t(std::max<int>(f.numSlots, int(f.paramTypes.size()))), nullptr);
    for (size_t i = 0; i < f.paramTypes.size(); ++i) slots_[i] = fn->getArg(unsigned(i + 1));
    llvm::Value* result = gen(f.body);
    b_.CreateRet(result);
  }

  // Instruction selection of one big function cannot be spread over threads; its parts can
  // (parallel_emit.h). In an entry this big, every large function that loops (has a fold)
  // stays a call: one call per loop costs little next to the loop it runs. Steps of outer
  // folds are left inline: they run once per iteration.
  void planOutlining(const std::vector<int>& entries) {
    if (!options_.inlineEverything) return;
    for (int e : entries) {
      uint64_t total = inlinedSize(program_, e);
      if (total < options_.outlineLoopsInEntriesAbove) continue;
      for (int f : loops_) {
        if (f != e && !foldSteps_.count(f) && inlinedSize(program_, f) >= options_.minOutlinedLoopSize) outlined_.insert(f);
      }
    }
  }

  // Static call sites of each function reachable from the entries, and each one's own size.
  void countCallSites(const std::vector<int>& entries) {
    std::vector<int> work(entries.begin(), entries.end());
    std::map<int, bool> seen;
    while (!work.empty()) {
      int f = work.back();
      work.pop_back();
      if (seen[f]) continue;
      seen[f] = true;
      uint64_t size = 0;
      std::vector<const Node*> nodes = {program_.functions[size_t(f)].body};
      while (!nodes.empty()) {
        const Node* n = nodes.back();
        nodes.pop_back();
        ++size;
        if (n->kind == Node::Kind::Fold) {
          loops_.insert(f);
          foldSteps_.insert(n->callee);
          // The step is a generated function whose body calls the user's step (lang's foldStep):
          // that one runs once per iteration too, so it stays inline as well.
          if (const Node* body = program_.functions[size_t(n->callee)].body; body && body->kind == Node::Kind::Call)
            foldSteps_.insert(body->callee);
        }
        if (n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) {
          ++callSites_[n->callee];
          work.push_back(n->callee);
        }
        for (const Node* a : n->args) nodes.push_back(a);
      }
      ownSize_[f] = size;
    }
  }

  // The ABI wrapper: void tex_entry_k(ptr args, ptr result, ptr ctx).
  void emitEntry(int index, llvm::Function* fn, size_t k) {
    const lang::ir::Function& f = program_.functions[size_t(index)];
    auto* type = llvm::FunctionType::get(llvm::Type::getVoidTy(context_), {ptrTy_, ptrTy_, ptrTy_}, false);
    auto* wrapper = llvm::Function::Create(type, llvm::Function::ExternalLinkage, entrySymbol(k), *module_);
    wrapper->addFnAttr(llvm::Attribute::NoUnwind);
    auto* block = llvm::BasicBlock::Create(context_, "entry", wrapper);
    b_.SetInsertPoint(block);
    llvm::Value* args = wrapper->getArg(0);
    std::vector<llvm::Value*> callArgs = {wrapper->getArg(2)};
    unsigned word = 0;
    for (const Type* t : f.paramTypes) callArgs.push_back(loadWords(args, t, word));
    llvm::Value* result = b_.CreateCall(fn, callArgs);
    word = 0;
    storeWords(wrapper->getArg(1), f.resultType, result, word);
    b_.CreateRetVoid();
  }

  llvm::Value* wordPtr(llvm::Value* base, unsigned word) { return b_.CreateConstInBoundsGEP1_32(i32_, base, word); }

  llvm::Value* loadWords(llvm::Value* base, const Type* t, unsigned& word) {
    switch (t->kind) {
      case TypeKind::Bool: return b_.CreateICmpNE(b_.CreateLoad(i32_, wordPtr(base, word++)), b_.getInt32(0));
      case TypeKind::Int:
      case TypeKind::Image:
      case TypeKind::Material: return b_.CreateLoad(i32_, wordPtr(base, word++));
      case TypeKind::Float: return b_.CreateLoad(f32_, wordPtr(base, word++));
      case TypeKind::Record:
      case TypeKind::Lambda: {
        llvm::Value* v = llvm::PoisonValue::get(lower(t));
        for (unsigned i = 0; i < t->fields.size(); ++i) v = b_.CreateInsertValue(v, loadWords(base, t->fields[i].second, word), {i});
        return v;
      }
      default:
        if (t->isFloatBased()) {
          llvm::Value* v = llvm::PoisonValue::get(lower(t));
          for (int i = 0; i < lanes(t); ++i) v = b_.CreateInsertElement(v, b_.CreateLoad(f32_, wordPtr(base, word++)), uint64_t(i));
          return v;
        }
        return llvm::PoisonValue::get(lower(t));  // no data
    }
  }

  void storeWords(llvm::Value* base, const Type* t, llvm::Value* v, unsigned& word) {
    switch (t->kind) {
      case TypeKind::Bool: b_.CreateStore(b_.CreateZExt(v, i32_), wordPtr(base, word++)); return;
      case TypeKind::Int:
      case TypeKind::Image:
      case TypeKind::Material:
      case TypeKind::Float: b_.CreateStore(v, wordPtr(base, word++)); return;
      case TypeKind::Record:
      case TypeKind::Lambda:
        for (unsigned i = 0; i < t->fields.size(); ++i) storeWords(base, t->fields[i].second, b_.CreateExtractValue(v, {i}), word);
        return;
      default:
        if (t->isFloatBased())
          for (int i = 0; i < lanes(t); ++i) b_.CreateStore(b_.CreateExtractElement(v, uint64_t(i)), wordPtr(base, word++));
        return;
    }
  }

  // ---- expressions ---------------------------------------------------------------------
  llvm::Value* gen(const Node* n) {
    switch (n->kind) {
      case Node::Kind::Const: return constant(n);
      case Node::Kind::Local: return slots_[size_t(n->slot)];
      case Node::Kind::Let:
        slots_[size_t(n->slot)] = gen(n->args[0]);
        return gen(n->args[1]);
      case Node::Kind::If: return genIf(n);
      case Node::Kind::And:
      case Node::Kind::Or: return genShortCircuit(n);
      case Node::Kind::Prim: return genPrim(n);
      case Node::Kind::Call: {
        std::vector<llvm::Value*> args;
        for (const Node* a : n->args) args.push_back(gen(a));
        if (inlinedAtCalls(n->callee)) return genInPlace(n, args);
        args.insert(args.begin(), ctx_);
        return b_.CreateCall(callee(n), args);
      }
      case Node::Kind::MakeRecord: {
        llvm::Value* v = llvm::PoisonValue::get(lower(n->type));
        for (unsigned i = 0; i < n->args.size(); ++i) v = b_.CreateInsertValue(v, gen(n->args[i]), {i});
        return v;
      }
      case Node::Kind::GetField: return b_.CreateExtractValue(gen(n->args[0]), {unsigned(n->index)});
      case Node::Kind::Fold: return genFold(n);
    }
    return llvm::PoisonValue::get(lower(n->type));
  }

  llvm::Value* constant(const Node* n) {
    const Type* t = n->type;
    if (t->kind == TypeKind::Int) return b_.getInt32(uint32_t(n->intValue));
    if (t->kind == TypeKind::Bool) return b_.getInt1(n->boolValue);
    if (t->kind == TypeKind::Image) return imageHandle(n->intValue);
    if (t->kind == TypeKind::Float) return llvm::ConstantFP::get(f32_, double(n->floatValue[0]));
    if (t->isFloatBased()) {
      std::vector<llvm::Constant*> lanesValues;
      for (int i = 0; i < lanes(t); ++i)
        lanesValues.push_back(llvm::ConstantFP::get(f32_, double(n->floatValue[t->kind == TypeKind::Spectrum ? 0 : i])));
      return llvm::ConstantVector::get(lanesValues);
    }
    return llvm::PoisonValue::get(lower(t));
  }

  // if (cond) yes() else no(), merged by a phi; `branchMetadata` annotates the branch.
  llvm::Value* diamond(llvm::Value* cond, llvm::MDNode* branchMetadata, const char* name,
                       const std::function<llvm::Value*()>& yes, const std::function<llvm::Value*()>& no) {
    llvm::Function* fn = b_.GetInsertBlock()->getParent();
    auto* yesBlock = llvm::BasicBlock::Create(context_, std::string(name) + ".then", fn);
    auto* noBlock = llvm::BasicBlock::Create(context_, std::string(name) + ".else", fn);
    auto* done = llvm::BasicBlock::Create(context_, std::string(name) + ".end", fn);
    llvm::BranchInst* branch = b_.CreateCondBr(cond, yesBlock, noBlock);
    if (branchMetadata) branch->setMetadata(branchMetadata == unpredictable_ ? llvm::LLVMContext::MD_unpredictable
                                                                              : llvm::LLVMContext::MD_prof,
                                            branchMetadata);
    b_.SetInsertPoint(yesBlock);
    llvm::Value* a = yes();
    llvm::BasicBlock* yesEnd = b_.GetInsertBlock();
    b_.CreateBr(done);
    b_.SetInsertPoint(noBlock);
    llvm::Value* c = no();
    llvm::BasicBlock* noEnd = b_.GetInsertBlock();
    b_.CreateBr(done);
    b_.SetInsertPoint(done);
    llvm::PHINode* phi = b_.CreatePHI(a->getType(), 2);
    phi->addIncoming(a, yesEnd);
    phi->addIncoming(c, noEnd);
    return phi;
  }

  llvm::Value* genIf(const Node* n) {
    // Texture conditions usually depend on hashed or noisy data: tell LLVM the branch is
    // unpredictable, so the selects SimplifyCFG makes of small diamonds stay branch-free.
    llvm::Value* cond = gen(n->args[0]);
    return diamond(cond, unpredictable_, "if", [&] { return gen(n->args[1]); }, [&] { return gen(n->args[2]); });
  }

  llvm::Value* genShortCircuit(const Node* n) {
    bool isAnd = n->kind == Node::Kind::And;
    llvm::Value* first = gen(n->args[0]);
    llvm::BasicBlock* firstEnd = b_.GetInsertBlock();
    llvm::Function* fn = firstEnd->getParent();
    auto* rhs = llvm::BasicBlock::Create(context_, isAnd ? "and.rhs" : "or.rhs", fn);
    auto* done = llvm::BasicBlock::Create(context_, isAnd ? "and.end" : "or.end", fn);
    if (isAnd) b_.CreateCondBr(first, rhs, done);
    else b_.CreateCondBr(first, done, rhs);
    b_.SetInsertPoint(rhs);
    llvm::Value* second = gen(n->args[1]);
    llvm::BasicBlock* rhsEnd = b_.GetInsertBlock();
    b_.CreateBr(done);
    b_.SetInsertPoint(done);
    llvm::PHINode* phi = b_.CreatePHI(i1_, 2);
    phi->addIncoming(b_.getInt1(!isAnd), firstEnd);
    phi->addIncoming(second, rhsEnd);
    return phi;
  }

  llvm::Value* genFold(const Node* n) {
    llvm::Value* count = gen(n->args[0]);
    llvm::Value* init = gen(n->args[1]);
    llvm::Value* closure = n->args.size() > 2 ? gen(n->args[2]) : nullptr;
    const bool inPlace = inlinedAtCalls(n->callee);
    llvm::Function* step = inPlace ? nullptr : callee(n);
    llvm::BasicBlock* pre = b_.GetInsertBlock();
    llvm::Function* fn = pre->getParent();
    auto* header = llvm::BasicBlock::Create(context_, "fold.header", fn);
    auto* body = llvm::BasicBlock::Create(context_, "fold.body", fn);
    auto* done = llvm::BasicBlock::Create(context_, "fold.end", fn);
    b_.CreateBr(header);
    b_.SetInsertPoint(header);
    llvm::PHINode* i = b_.CreatePHI(i32_, 2, "i");
    llvm::PHINode* acc = b_.CreatePHI(lower(n->type), 2, "acc");
    i->addIncoming(b_.getInt32(0), pre);
    acc->addIncoming(init, pre);
    b_.CreateCondBr(b_.CreateICmpSLT(i, count), body, done);
    b_.SetInsertPoint(body);
    std::vector<llvm::Value*> args;
    if (closure) args.push_back(closure);
    args.push_back(acc);
    args.push_back(i);
    llvm::Value* next = nullptr;
    if (inPlace) {
      next = genInPlace(n, args);
    } else {
      args.insert(args.begin(), ctx_);
      next = b_.CreateCall(step, args);
    }
    llvm::BasicBlock* bodyEnd = b_.GetInsertBlock();
    i->addIncoming(b_.CreateAdd(i, b_.getInt32(1), "", /*HasNUW=*/false, /*HasNSW=*/true), bodyEnd);
    acc->addIncoming(next, bodyEnd);
    b_.CreateBr(header);
    b_.SetInsertPoint(done);
    return acc;
  }

  llvm::Value* intrinsic(llvm::Intrinsic::ID id, std::vector<llvm::Value*> args) {
    return b_.CreateIntrinsic(id, {args[0]->getType()}, args);
  }

  // IEEE 754-2019 minimumNumber / maximumNumber, as the interpreter (docs/language.md section
  // 5): minnum / maxnum avoid NaN but may return either zero when the operands compare equal
  // (constant folding and minss differ); for equal operands OR-ing (min) or AND-ing (max) the
  // bits picks -0 < +0 and leaves equal non-zero values unchanged.
  llvm::Value* genMinMaxNumber(bool isMin, llvm::Value* x, llvm::Value* y) {
    llvm::Value* r = intrinsic(isMin ? llvm::Intrinsic::minnum : llvm::Intrinsic::maxnum, {x, y});
    llvm::Type* t = x->getType();
    llvm::Type* bitsType = t->isVectorTy() ? llvm::VectorType::get(i32_, llvm::cast<llvm::VectorType>(t)->getElementCount())
                                           : static_cast<llvm::Type*>(i32_);
    llvm::Value* xb = b_.CreateBitCast(x, bitsType);
    llvm::Value* yb = b_.CreateBitCast(y, bitsType);
    llvm::Value* merged = b_.CreateBitCast(isMin ? b_.CreateOr(xb, yb) : b_.CreateAnd(xb, yb), t);
    return b_.CreateSelect(b_.CreateFCmpOEQ(x, y), merged, r);
  }

  // Calls a float libm function lane by lane (for functions without an LLVM intrinsic).
  llvm::Value* libmLanes(const char* name, std::vector<llvm::Value*> args) {
    std::vector<llvm::Type*> params(args.size(), f32_);
    llvm::FunctionCallee callee = module_->getOrInsertFunction(name, llvm::FunctionType::get(f32_, params, false));
    if (auto* f = llvm::dyn_cast<llvm::Function>(callee.getCallee())) {
      f->setDoesNotThrow();
      f->setWillReturn();
    }
    llvm::Type* type = args[0]->getType();
    if (!type->isVectorTy()) return b_.CreateCall(callee, args);
    unsigned count = unsigned(llvm::cast<llvm::FixedVectorType>(type)->getNumElements());
    llvm::Value* result = llvm::PoisonValue::get(type);
    for (unsigned lane = 0; lane < count; ++lane) {
      std::vector<llvm::Value*> laneArgs;
      for (llvm::Value* a : args) laneArgs.push_back(b_.CreateExtractElement(a, uint64_t(lane)));
      result = b_.CreateInsertElement(result, b_.CreateCall(callee, laneArgs), uint64_t(lane));
    }
    return result;
  }

  llvm::Value* doubleConst(llvm::Type* like, double value) {
    llvm::Constant* c = llvm::ConstantFP::get(llvm::Type::getDoubleTy(context_), value);
    return llvm::ConstantVector::getSplat(llvm::cast<llvm::FixedVectorType>(like)->getElementCount(), c);
  }

  // sin or cos of every lane of a Spectrum at once: Cody-Waite reduction by pi/2 and Taylor
  // polynomials in double precision, rounded once to float, so each lane is within about
  // half an ulp of the exact value (docs/language.md allows 4 ulp; the C library's sinf/cosf
  // are within 1). Lanes beyond |x| <= 65536, and NaN or infinities, take the C library path
  // for the whole vector.
  llvm::Value* spectralSinCos(llvm::Value* x, bool cosine) {
    auto* vt = llvm::cast<llvm::FixedVectorType>(x->getType());
    llvm::Value* absX = b_.CreateIntrinsic(llvm::Intrinsic::fabs, {vt}, {x});
    llvm::Value* inRange = b_.CreateAndReduce(b_.CreateFCmpOLE(absX, floatConst(vt, 65536.0f)));
    return diamond(inRange, likely_, "sincos", [&] { return sinCosFast(x, cosine); },
                   [&] { return libmLanes(cosine ? "cosf" : "sinf", {x}); });
  }

  llvm::Value* sinCosFast(llvm::Value* x, bool cosine) {
    auto* vt = llvm::cast<llvm::FixedVectorType>(x->getType());
    unsigned count = unsigned(vt->getNumElements());
    auto* dt = llvm::FixedVectorType::get(llvm::Type::getDoubleTy(context_), count);
    auto* it = llvm::FixedVectorType::get(i32_, count);
    llvm::Value* xd = b_.CreateFPExt(x, dt);
    llvm::Value* k = b_.CreateIntrinsic(llvm::Intrinsic::rint, {dt}, {b_.CreateFMul(xd, doubleConst(dt, 0.63661977236758134308))});
    // pi/2 = hi + lo with hi's 33 leading bits, so k * hi is exact for |k| < 2^20.
    llvm::Value* r = b_.CreateFSub(b_.CreateFSub(xd, b_.CreateFMul(k, doubleConst(dt, 1.57079632673412561417e+00))),
                                   b_.CreateFMul(k, doubleConst(dt, 6.07710050650619224932e-11)));
    llvm::Value* r2 = b_.CreateFMul(r, r);
    auto horner = [&](std::initializer_list<double> coefficients) {
      llvm::Value* acc = nullptr;
      for (double c : coefficients) acc = acc ? b_.CreateFAdd(b_.CreateFMul(acc, r2), doubleConst(dt, c)) : doubleConst(dt, c);
      return acc;
    };
    // sin r = r (1 - r^2/3! + ... - r^14/15!), cos r = 1 - r^2/2! + ... + r^16/16!, |r| <= pi/4.
    llvm::Value* sinR = b_.CreateFMul(r, horner({-1.0 / 1307674368000.0, 1.0 / 6227020800.0, -1.0 / 39916800.0, 1.0 / 362880.0,
                                                -1.0 / 5040.0, 1.0 / 120.0, -1.0 / 6.0, 1.0}));
    llvm::Value* cosR = horner({1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0, -1.0 / 3628800.0,
                                1.0 / 40320.0, -1.0 / 720.0, 1.0 / 24.0, -0.5, 1.0});
    // Quadrant q = k mod 4 (cos x = sin(x + pi/2): shift q by one).
    llvm::Value* q = b_.CreateFPToSI(k, it);
    if (cosine) q = b_.CreateAdd(q, llvm::ConstantVector::getSplat(it->getElementCount(), b_.getInt32(1)));
    auto splatI = [&](uint32_t v) { return llvm::ConstantVector::getSplat(it->getElementCount(), b_.getInt32(v)); };
    llvm::Value* useCos = b_.CreateICmpNE(b_.CreateAnd(q, splatI(1)), splatI(0));
    llvm::Value* negate = b_.CreateICmpNE(b_.CreateAnd(q, splatI(2)), splatI(0));
    llvm::Value* value = b_.CreateSelect(useCos, cosR, sinR);
    value = b_.CreateSelect(negate, b_.CreateFNeg(value), value);
    llvm::Value* fastResult = b_.CreateFPTrunc(value, vt);
    // sin(-0) is -0: the reduction would give +0.
    if (!cosine) fastResult = b_.CreateSelect(b_.CreateFCmpOEQ(x, floatConst(vt, 0.0f)), x, fastResult);
    return fastResult;
  }

  llvm::Value* floatConst(llvm::Type* like, float value) {
    llvm::Constant* c = llvm::ConstantFP::get(f32_, double(value));
    if (auto* vt = llvm::dyn_cast<llvm::FixedVectorType>(like)) return llvm::ConstantVector::getSplat(vt->getElementCount(), c);
    return c;
  }

  llvm::Value* safeIntDivision(llvm::Value* a, llvm::Value* d, bool remainder) {
    // x / 0 == 0 and x % 0 == 0; INT_MIN / -1 == INT_MIN and its % is 0 (docs/language.md 5).
    llvm::Value* zero = b_.CreateICmpEQ(d, b_.getInt32(0));
    llvm::Value* overflow = b_.CreateAnd(b_.CreateICmpEQ(a, b_.getInt32(0x80000000u)), b_.CreateICmpEQ(d, b_.getInt32(uint32_t(-1))));
    llvm::Value* safe = b_.CreateSelect(b_.CreateOr(zero, overflow), b_.getInt32(1), d);
    llvm::Value* q = remainder ? b_.CreateSRem(a, safe) : b_.CreateSDiv(a, safe);
    llvm::Value* special = remainder ? static_cast<llvm::Value*>(b_.getInt32(0)) : b_.CreateSelect(zero, b_.getInt32(0), a);
    return b_.CreateSelect(b_.CreateOr(zero, overflow), special, q);
  }

  // int(x): truncation with NaN -> 0 and saturation (docs/language.md 5). In range (the
  // common case) it is one truncating conversion; the saturating fix-up sits behind a branch
  // marked unlikely, so hot code pays no compares and conditional moves for it.
  llvm::Value* floatToInt(llvm::Value* x) {
    auto saturating = [&]() -> llvm::Value* { return b_.CreateIntrinsic(llvm::Intrinsic::fptosi_sat, {i32_, f32_}, {x}); };
    if (!options_.inlineEverything) return saturating();  // quick mode: fewer blocks compile faster
    llvm::Value* inRange = b_.CreateFCmpOLT(b_.CreateIntrinsic(llvm::Intrinsic::fabs, {f32_}, {x}),
                                            llvm::ConstantFP::get(f32_, 2147483648.0));
    return diamond(inRange, likely_, "ftoi", [&]() -> llvm::Value* { return b_.CreateFPToSI(x, i32_); }, saturating);
  }

  llvm::Value* allLanesEqual(llvm::Value* x, llvm::Value* y) {
    llvm::Value* eq = b_.CreateFCmpOEQ(x, y);
    if (!eq->getType()->isVectorTy()) return eq;
    return b_.CreateAndReduce(eq);
  }

  llvm::Value* genPrim(const Node* n) {
    std::vector<llvm::Value*> a;
    for (const Node* arg : n->args) a.push_back(gen(arg));
    using ID = llvm::Intrinsic::ID;
    switch (n->prim) {
      case Prim::FAdd: return b_.CreateFAdd(a[0], a[1]);
      case Prim::FSub: return b_.CreateFSub(a[0], a[1]);
      case Prim::FMul: return b_.CreateFMul(a[0], a[1]);
      case Prim::FDiv: return b_.CreateFDiv(a[0], a[1]);
      case Prim::FRem: return b_.CreateFRem(a[0], a[1]);
      case Prim::FNeg: return b_.CreateFNeg(a[0]);
      case Prim::FMin: return genMinMaxNumber(true, a[0], a[1]);
      case Prim::FMax: return genMinMaxNumber(false, a[0], a[1]);
      case Prim::FAbs: return intrinsic(ID(llvm::Intrinsic::fabs), a);
      case Prim::FSign: {
        llvm::Value* x = a[0];
        llvm::Type* t = x->getType();
        llvm::Value* zero = floatConst(t, 0.0f);
        return b_.CreateSelect(b_.CreateFCmpOGT(x, zero), floatConst(t, 1.0f),
                               b_.CreateSelect(b_.CreateFCmpOLT(x, zero), floatConst(t, -1.0f), x));
      }
      case Prim::FFloor: return intrinsic(ID(llvm::Intrinsic::floor), a);
      case Prim::FCeil: return intrinsic(ID(llvm::Intrinsic::ceil), a);
      case Prim::FTrunc: return intrinsic(ID(llvm::Intrinsic::trunc), a);
      case Prim::FRound: return intrinsic(ID(llvm::Intrinsic::round), a);
      case Prim::FSqrt: return intrinsic(ID(llvm::Intrinsic::sqrt), a);
      case Prim::FExp: return libmLanes("expf", a);
      case Prim::FExp2: return libmLanes("exp2f", a);
      case Prim::FLog: return libmLanes("logf", a);
      case Prim::FLog2: return libmLanes("log2f", a);
      case Prim::FSin: return n->type->kind == TypeKind::Spectrum && lanes(n->type) >= 4 ? spectralSinCos(a[0], false) : libmLanes("sinf", a);
      case Prim::FCos: return n->type->kind == TypeKind::Spectrum && lanes(n->type) >= 4 ? spectralSinCos(a[0], true) : libmLanes("cosf", a);
      case Prim::FTan: return libmLanes("tanf", a);
      case Prim::FAsin: return libmLanes("asinf", a);
      case Prim::FAcos: return libmLanes("acosf", a);
      case Prim::FAtan: return libmLanes("atanf", a);
      case Prim::FSinh: return libmLanes("sinhf", a);
      case Prim::FCosh: return libmLanes("coshf", a);
      case Prim::FTanh: return libmLanes("tanhf", a);
      case Prim::FPow: return libmLanes("powf", a);
      case Prim::FAtan2: return libmLanes("atan2f", a);
      case Prim::FStep: {
        llvm::Type* t = a[1]->getType();
        return b_.CreateSelect(b_.CreateFCmpOLT(a[1], a[0]), floatConst(t, 0.0f), floatConst(t, 1.0f));
      }
      case Prim::FLt: return b_.CreateFCmpOLT(a[0], a[1]);
      case Prim::FLe: return b_.CreateFCmpOLE(a[0], a[1]);
      case Prim::FGt: return b_.CreateFCmpOGT(a[0], a[1]);
      case Prim::FGe: return b_.CreateFCmpOGE(a[0], a[1]);
      case Prim::FEq: return allLanesEqual(a[0], a[1]);
      case Prim::FNe: return b_.CreateNot(allLanesEqual(a[0], a[1]));
      case Prim::FIsNan: return b_.CreateFCmpUNO(a[0], a[0]);
      case Prim::FIsInf:
        return b_.CreateFCmpOEQ(intrinsic(ID(llvm::Intrinsic::fabs), {a[0]}),
                                llvm::ConstantFP::getInfinity(f32_));
      case Prim::IAdd: return b_.CreateAdd(a[0], a[1]);
      case Prim::ISub: return b_.CreateSub(a[0], a[1]);
      case Prim::IMul: return b_.CreateMul(a[0], a[1]);
      case Prim::IDiv: return safeIntDivision(a[0], a[1], false);
      case Prim::IRem: return safeIntDivision(a[0], a[1], true);
      case Prim::INeg: return b_.CreateSub(b_.getInt32(0), a[0]);
      case Prim::IAnd: return b_.CreateAnd(a[0], a[1]);
      case Prim::IOr: return b_.CreateOr(a[0], a[1]);
      case Prim::IXor: return b_.CreateXor(a[0], a[1]);
      case Prim::IShl: return b_.CreateShl(a[0], b_.CreateAnd(a[1], b_.getInt32(31)));
      case Prim::IShr: return b_.CreateAShr(a[0], b_.CreateAnd(a[1], b_.getInt32(31)));
      case Prim::INot: return b_.CreateNot(a[0]);
      case Prim::IMin: return intrinsic(ID(llvm::Intrinsic::smin), a);
      case Prim::IMax: return intrinsic(ID(llvm::Intrinsic::smax), a);
      case Prim::IAbs: return b_.CreateIntrinsic(llvm::Intrinsic::abs, {i32_}, {a[0], b_.getInt1(false)});
      case Prim::ILt: return b_.CreateICmpSLT(a[0], a[1]);
      case Prim::ILe: return b_.CreateICmpSLE(a[0], a[1]);
      case Prim::IGt: return b_.CreateICmpSGT(a[0], a[1]);
      case Prim::IGe: return b_.CreateICmpSGE(a[0], a[1]);
      case Prim::IEq: return b_.CreateICmpEQ(a[0], a[1]);
      case Prim::INe: return b_.CreateICmpNE(a[0], a[1]);
      case Prim::BNot: return b_.CreateNot(a[0]);
      case Prim::BEq: return b_.CreateICmpEQ(a[0], a[1]);
      case Prim::BNe: return b_.CreateICmpNE(a[0], a[1]);
      case Prim::IntToFloat: return b_.CreateSIToFP(a[0], f32_);
      case Prim::FloatToInt: return floatToInt(a[0]);
      case Prim::Splat: return b_.CreateVectorSplat(unsigned(lanes(n->type)), a[0]);
      case Prim::Concat: {
        llvm::Value* v = llvm::PoisonValue::get(lower(n->type));
        uint64_t at = 0;
        for (size_t k = 0; k < a.size(); ++k) {
          if (!a[k]->getType()->isVectorTy()) {
            v = b_.CreateInsertElement(v, a[k], at++);
            continue;
          }
          int count = lanes(n->args[k]->type);
          for (int i = 0; i < count; ++i) v = b_.CreateInsertElement(v, b_.CreateExtractElement(a[k], uint64_t(i)), at++);
        }
        return v;
      }
      case Prim::Swizzle: {
        if (n->lanes.size() == 1) return b_.CreateExtractElement(a[0], uint64_t(n->lanes[0]));
        std::vector<int> mask(n->lanes.begin(), n->lanes.end());
        return b_.CreateShuffleVector(a[0], mask);
      }
      case Prim::Dot: {
        int count = lanes(n->args[0]->type);
        llvm::Value* sum = nullptr;
        for (int i = 0; i < count; ++i) {
          llvm::Value* p = b_.CreateFMul(b_.CreateExtractElement(a[0], uint64_t(i)), b_.CreateExtractElement(a[1], uint64_t(i)));
          sum = sum ? b_.CreateFAdd(sum, p) : p;
        }
        return sum;
      }
      case Prim::Wavelengths: {
        // ShadingContext.lambdaNm is its first member.
        llvm::Value* v = llvm::PoisonValue::get(lower(n->type));
        for (int i = 0; i < options_.wavelengths; ++i)
          v = b_.CreateInsertElement(v, b_.CreateLoad(f32_, b_.CreateConstInBoundsGEP1_32(f32_, ctx_, unsigned(i))), uint64_t(i));
        return v;
      }
      case Prim::MatDiffuse:
      case Prim::MatEmission:
      case Prim::MatMix:
      case Prim::MatDielectric:
      case Prim::MatConductor:
      case Prim::MatThinDielectric:
      case Prim::MatGlossy:
      case Prim::MatGlossyDielectric:
      case Prim::MatLayer:
      case Prim::MatScale:
      case Prim::MatAdd:
      case Prim::MatSheen: return genMaterialNode(n, a);
      case Prim::ImageNearest:
      case Prim::ImageBilinear:
      case Prim::ImageTrilinear: return genImageLookup(n, a);
      case Prim::ImageSize: {
        llvm::AllocaInst* out = entryAlloca(llvm::ArrayType::get(f32_, 2));
        llvm::FunctionCallee size = runtimeFunction("tex_rt_image_size", llvm::Type::getVoidTy(context_), {i32_, ptrTy_});
        b_.CreateCall(size, {a[0], out});
        return b_.CreateAlignedLoad(lower(n->type), out, llvm::Align(4));
      }
      case Prim::RgbReflectance:
      case Prim::RgbUnbounded:
      case Prim::RgbIlluminant: {
        // tex_rt_rgb_spectrum(use, rgb, ctx, out): the renderer's upsampling at the context's
        // wavelengths (lang/rgb_upsampling.h), the same function the interpreter calls.
        const int use = n->prim == Prim::RgbReflectance ? 0 : n->prim == Prim::RgbUnbounded ? 1 : 2;
        llvm::AllocaInst* rgb = entryAlloca(llvm::ArrayType::get(f32_, 3));
        for (int k = 0; k < 3; ++k)
          b_.CreateStore(b_.CreateExtractElement(a[0], uint64_t(k)), b_.CreateConstInBoundsGEP1_32(f32_, rgb, unsigned(k)));
        llvm::AllocaInst* out = entryAlloca(llvm::ArrayType::get(f32_, kMaxWavelengths));
        llvm::FunctionCallee f =
            runtimeFunction("tex_rt_rgb_spectrum", llvm::Type::getVoidTy(context_), {i32_, ptrTy_, ptrTy_, ptrTy_});
        b_.CreateCall(f, {b_.getInt32(uint32_t(use)), rgb, ctx_, out});
        return b_.CreateAlignedLoad(lower(n->type), out, llvm::Align(4));
      }
    }
    return llvm::PoisonValue::get(lower(n->type));
  }

  // A material node, written straight into the caller's arena (docs/abi.md, "Materials"):
  // the append is inline, so the node is not built on the stack and copied by a call (that
  // copy had to read it back a word at a time to avoid store-forwarding stalls). Operands go
  // into the fields in the order of lang::ir::MaterialShape over a zeroed node.
  llvm::Value* genMaterialNode(const Node* n, const std::vector<llvm::Value*>& a) {
    const lang::ir::MaterialShape& shape = *lang::ir::materialShape(n->prim);
    llvm::Type* i8 = b_.getInt8Ty();
    const auto field = [&](llvm::Value* base, size_t byteOffset) {
      return b_.CreateConstInBoundsGEP1_64(i8, base, uint64_t(byteOffset));
    };
    llvm::Function* fn = b_.GetInsertBlock()->getParent();
    llvm::BasicBlock* haveCtx = llvm::BasicBlock::Create(context_, "closure.ctx", fn);
    llvm::BasicBlock* haveArena = llvm::BasicBlock::Create(context_, "closure.arena", fn);
    llvm::BasicBlock* full = llvm::BasicBlock::Create(context_, "closure.full", fn);
    llvm::BasicBlock* write = llvm::BasicBlock::Create(context_, "closure.write", fn);
    llvm::BasicBlock* done = llvm::BasicBlock::Create(context_, "closure.done", fn);
    // No context or no arena: the Material is -1 and nothing is written.
    llvm::BasicBlock* start = b_.GetInsertBlock();
    b_.CreateCondBr(b_.CreateIsNotNull(ctx_), haveCtx, done, likely_);
    b_.SetInsertPoint(haveCtx);
    llvm::Value* arena = b_.CreateAlignedLoad(ptrTy_, field(ctx_, offsetof(ShadingContext, arena)), llvm::Align(8));
    b_.CreateCondBr(b_.CreateIsNotNull(arena), haveArena, done, likely_);
    b_.SetInsertPoint(haveArena);
    llvm::Value* countPtr = field(arena, offsetof(ClosureArena, count));
    llvm::Value* count = b_.CreateAlignedLoad(i32_, countPtr, llvm::Align(4));
    llvm::Value* capacity = b_.CreateAlignedLoad(i32_, field(arena, offsetof(ClosureArena, capacity)), llvm::Align(4));
    b_.CreateCondBr(b_.CreateICmpSLT(count, capacity), write, full, likely_);
    // A full arena drops the node and marks the material invalid.
    b_.SetInsertPoint(full);
    b_.CreateAlignedStore(b_.getInt32(1), field(arena, offsetof(ClosureArena, overflow)), llvm::Align(4));
    b_.CreateBr(done);

    b_.SetInsertPoint(write);
    llvm::Value* nodes = b_.CreateAlignedLoad(ptrTy_, field(arena, offsetof(ClosureArena, nodes)), llvm::Align(8));
    llvm::Value* node = b_.CreateInBoundsGEP(
        i8, nodes, b_.CreateMul(b_.CreateSExt(count, b_.getInt64Ty()), b_.getInt64(sizeof(ClosureNode))));
    b_.CreateMemSet(node, b_.getInt8(0), uint64_t(sizeof(ClosureNode)), llvm::MaybeAlign(4));
    auto at = [&](size_t byteOffset) { return field(node, byteOffset); };
    b_.CreateStore(b_.getInt32(shape.kind), at(offsetof(ClosureNode, kind)));
    size_t operand = 0;
    b_.CreateStore(shape.children > 0 ? a[operand++] : b_.getInt32(uint32_t(-1)), at(offsetof(ClosureNode, a)));
    b_.CreateStore(shape.children > 1 ? a[operand++] : b_.getInt32(uint32_t(-1)), at(offsetof(ClosureNode, b)));
    auto vectorParam = [&](size_t kindOffset, size_t valuesOffset) {
      const Type* t = n->args[operand]->type;
      ClosureParam kind = t->kind == TypeKind::Color ? ClosureParam::Color : ClosureParam::Spectrum;
      b_.CreateStore(b_.getInt32(uint32_t(kind)), at(kindOffset));
      for (int k = 0; k < lanes(t); ++k)
        b_.CreateStore(b_.CreateExtractElement(a[operand], uint64_t(k)), at(valuesOffset + 4 * size_t(k)));
      ++operand;
    };
    if (shape.params > 0) vectorParam(offsetof(ClosureNode, paramKind), offsetof(ClosureNode, params));
    if (shape.params > 1) vectorParam(offsetof(ClosureNode, param2Kind), offsetof(ClosureNode, params2));
    const int scalars = lang::ir::materialScalarCount(n, shape);
    for (int i = 0; i < scalars; ++i)
      b_.CreateStore(a[operand++], at(offsetof(ClosureNode, scalars) + 4 * size_t(i)));
    if (shape.weight) b_.CreateStore(a[operand++], at(offsetof(ClosureNode, weight)));
    const uint32_t anisotropic = scalars != shape.scalars ? kClosureAnisotropic : 0u;
    if (shape.params > 0)
      b_.CreateStore(b_.getInt32(dependence_.flags(dependenceContext_, n) | anisotropic), at(offsetof(ClosureNode, flags)));
    b_.CreateAlignedStore(b_.CreateAdd(count, b_.getInt32(1)), countPtr, llvm::Align(4));
    b_.CreateBr(done);

    b_.SetInsertPoint(done);
    llvm::PHINode* index = b_.CreatePHI(i32_, 4, "closure.index");
    index->addIncoming(b_.getInt32(uint32_t(-1)), start);
    index->addIncoming(b_.getInt32(uint32_t(-1)), haveCtx);
    index->addIncoming(b_.getInt32(uint32_t(-1)), full);
    index->addIncoming(count, write);
    return index;
  }

  llvm::FunctionCallee runtimeFunction(const char* name, llvm::Type* result, std::vector<llvm::Type*> params) {
    llvm::FunctionCallee callee = module_->getOrInsertFunction(name, llvm::FunctionType::get(result, params, false));
    if (auto* f = llvm::dyn_cast<llvm::Function>(callee.getCallee())) f->setDoesNotThrow();
    return callee;
  }

  // An Image constant: handles are process-specific, so the code names the file and its identity
  // (size, mtime: a value made before the file changed keeps the old image, as in the
  // interpreter) and asks the runtime once per module (docs/abi.md, "Images"); the answer is
  // cached in a global.
  llvm::Value* imageHandle(int32_t handle) {
    const lang::LoadedImage* image = lang::ImageTable::global().get(handle);
    if (!image) return b_.getInt32(uint32_t(-1));
    auto key = std::make_tuple(image->path, image->data, image->fileBytes, image->mtimeNs);
    auto it = imageGlobals_.find(key);
    if (it == imageGlobals_.end()) {
      llvm::Constant* text = llvm::ConstantDataArray::getString(context_, image->path);
      auto* path = new llvm::GlobalVariable(*module_, text->getType(), true, llvm::GlobalValue::PrivateLinkage, text, "image.path");
      auto* cache = new llvm::GlobalVariable(*module_, i32_, false, llvm::GlobalValue::InternalLinkage,
                                             b_.getInt32(uint32_t(-1)), "image.handle");
      cache->setAlignment(llvm::Align(4));
      it = imageGlobals_.emplace(key, std::make_pair(path, cache)).first;
    }
    llvm::FunctionCallee resolve =
        runtimeFunction("tex_rt_image_handle", i32_, {ptrTy_, i32_, ptrTy_, b_.getInt64Ty(), b_.getInt64Ty()});
    return b_.CreateCall(resolve, {it->second.first, b_.getInt32(image->data ? 1 : 0), it->second.second,
                                   b_.getInt64(image->fileBytes), b_.getInt64(uint64_t(image->mtimeNs))});
  }

  // (image, uv, duvdx, duvdy, wrap) -> RGBA through tex_rt_image_lookup, the interpreter's code.
  llvm::Value* genImageLookup(const Node* n, const std::vector<llvm::Value*>& a) {
    lang::ImageFilter filter = n->prim == Prim::ImageNearest    ? lang::ImageFilter::Nearest
                               : n->prim == Prim::ImageBilinear ? lang::ImageFilter::Bilinear
                                                                : lang::ImageFilter::Trilinear;
    llvm::AllocaInst* out = entryAlloca(llvm::ArrayType::get(f32_, 4));
    llvm::FunctionCallee lookup = runtimeFunction("tex_rt_image_lookup", llvm::Type::getVoidTy(context_),
                                                  {i32_, i32_, i32_, f32_, f32_, f32_, f32_, f32_, f32_, ptrTy_});
    auto lane = [&](llvm::Value* v, uint64_t i) { return b_.CreateExtractElement(v, i); };
    b_.CreateCall(lookup, {b_.getInt32(uint32_t(filter)), a[0], a[4], lane(a[1], 0), lane(a[1], 1), lane(a[2], 0),
                           lane(a[2], 1), lane(a[3], 0), lane(a[3], 1), out});
    return b_.CreateAlignedLoad(lower(n->type), out, llvm::Align(4));
  }

  llvm::AllocaInst* entryAlloca(llvm::Type* type) {
    llvm::Function* fn = b_.GetInsertBlock()->getParent();
    llvm::IRBuilder<> entry(&fn->getEntryBlock(), fn->getEntryBlock().begin());
    return entry.CreateAlloca(type);
  }

  llvm::LLVMContext& context_;
  const lang::ir::Program& program_;
  CodegenOptions options_;
  std::unique_ptr<llvm::Module> module_;
  llvm::IRBuilder<> b_;
  llvm::Type *ptrTy_, *f32_, *i32_, *i1_;
  llvm::MDNode* unpredictable_;  // for if-expressions
  llvm::MDNode* likely_;         // branch weights: the first successor is the common case
  lang::ir::WavelengthDependence dependence_;  // closure flags, analysed once per compile
  std::map<FunctionKey, llvm::Function*> functions_;
  std::unordered_map<const Type*, llvm::Type*> lowered_;
  std::map<std::tuple<std::string, bool, uint64_t, int64_t>, std::pair<llvm::GlobalVariable*, llvm::GlobalVariable*>>
      imageGlobals_;  // (path, data, bytes, mtime) -> (path, cache)
  std::map<int, uint64_t> callSites_, ownSize_;
  std::set<int> loops_;      // functions whose own body has a fold
  std::set<int> foldSteps_;  // functions called as a fold's step
  std::set<int> outlined_;   // functions kept out of line so a big entry can be emitted in parts
  std::map<int, bool> inlinedAtCalls_;
  std::vector<FunctionKey> pending_;
  int dependenceContext_ = -1;  // the wavelength-dependence context of the function being emitted
  llvm::Value* ctx_ = nullptr;
  std::vector<llvm::Value*> slots_;
};

}  // namespace

std::unique_ptr<llvm::Module> generateModule(llvm::LLVMContext& context, const lang::ir::Program& program,
                                             const std::vector<int>& entries, const CodegenOptions& options,
                                             std::string& error) {
  return Codegen(context, program, options).run(entries, error);
}

}  // namespace tex::compiler
