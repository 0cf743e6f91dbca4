// Internal to lang/: builds the typed core IR of one function instance while type-checking
// its body (checker.cpp), including the builtin calls (builtins.cpp).
#pragma once
#include "lang/session_impl.h"

namespace tex::lang {

struct LocalVar {
  std::string name;
  const Type* type;
  int slot;
  const Type* fnAnnotation;  // a `(A) -> R` annotation to apply at calls, or null
};

// A typed argument on its way into a call.
struct TypedArg {
  std::string name;  // empty when positional
  Span nameSpan;
  Span span;
  ir::Node* node;
};

// A builtin parameter that may be given by name; `optional` ones default to the Float `value`.
struct BuiltinParam {
  std::string name;
  bool optional = false;
  float value = 0.0f;
};

class Builder {
 public:
  Builder(Session::Impl& impl, ModuleInfo* module);

  ir::Node* check(const Expr* e);
  ir::Node* coerce(ir::Node* n, const Type* target, Span span, const char* context);
  int declareLocal(const std::string& name, const Type* type, const Type* fnAnnotation = nullptr);
  void popLocals(size_t count) { locals_.resize(locals_.size() - count); }
  int numSlots() const { return numSlots_; }
  bool hadError() const { return hadError_; }

  // ---- node helpers -----------------------------------------------------------------
  ir::Node* errorNode(Span span);
  ir::Node* constFloat(float v, Span span);
  ir::Node* constInt(int32_t v, Span span);
  ir::Node* constBool(bool v, Span span);
  ir::Node* constLanes(const Type* type, const float* values, Span span);
  ir::Node* prim(ir::Prim op, const Type* type, std::vector<ir::Node*> args, Span span);
  ir::Node* local(int slot, const Type* type, Span span);
  ir::Node* let(int slot, ir::Node* value, ir::Node* body, Span span);
  ir::Node* splatTo(ir::Node* scalar, const Type* target, Span span);
  ir::Node* toFloat(ir::Node* n, Span span);  // Int -> Float, others unchanged
  // Binds a value to a fresh slot so it can be used several times; returns the Local node.
  ir::Node* bindOnce(ir::Node* value, std::vector<std::pair<int, ir::Node*>>& lets);
  ir::Node* wrapLets(const std::vector<std::pair<int, ir::Node*>>& lets, ir::Node* body);

  // Applies a callable value (FuncRef, BuiltinRef, Lambda) to typed arguments.
  ir::Node* apply(ir::Node* callee, Span calleeSpan, std::vector<TypedArg> args, Span callSpan,
                  const Type* fnAnnotation);
  // Instantiates a callable with argument types; returns the IR function index or -1.
  int instantiateCallable(const Type* callable, const std::vector<const Type*>& args, Span at);
  // fold's step: a function of (closure for a lambda, acc, i) whose body is the ordinary call
  // f(acc, i); returns its IR function index or -1 (builtins.cpp).
  int foldStep(ir::Node* f, const Type* acc, Span at);

  // builtins.cpp
  ir::Node* builtinCall(const std::string& name, std::vector<TypedArg> args, Span calleeSpan, Span callSpan);
  bool orderBuiltinArgs(const std::string& name, const std::vector<BuiltinParam>& params, std::vector<TypedArg>& args,
                        Span calleeSpan, Span callSpan);
  ir::Node* builtinConstant(const std::string& name, Span span);
  // image("path") and image_data("path"): loads the file at check time (image_builtins.cpp).
  ir::Node* imageCall(const std::string& name, const Expr* call, Span calleeSpan);
  // sample, sample_nearest, sample_alpha, sample_filtered, image_size; null if `name` is none.
  ir::Node* imageBuiltin(const std::string& name, std::vector<TypedArg>& args, Span calleeSpan, Span callSpan);

  Diagnostic* error(const std::string& code, Span span, std::string message, std::string help = {});

  Session::Impl& impl;
  ir::Program& program;
  TypeTable& types;
  ModuleInfo* module;

 private:
  const LocalVar* findLocal(const std::string& name) const;
  ir::Node* checkName(const Expr* e);
  ir::Node* checkUnary(const Expr* e);
  ir::Node* checkBinary(const Expr* e);
  ir::Node* checkCall(const Expr* e);
  ir::Node* checkField(const Expr* e);
  ir::Node* checkLet(const Expr* e);
  ir::Node* checkIf(const Expr* e);
  ir::Node* checkLambda(const Expr* e);
  ir::Node* checkRecord(const Expr* e);
  ir::Node* checkRecordUpdate(const Expr* e);
  ir::Node* declValue(const FunctionDecl* decl, Span span);
  ir::Node* callDecl(const FunctionDecl* decl, std::vector<TypedArg> args, Span calleeSpan, Span callSpan);
  ir::Node* swizzle(ir::Node* base, const std::string& letters, Span span);
  std::vector<TypedArg> checkArgs(const Expr* call);

  std::vector<LocalVar> locals_;
  int numSlots_ = 0;
  bool hadError_ = false;
};

// Numeric promotion of two operands (docs/language.md section 3); false if incompatible.
bool unifyNumeric(Builder& b, ir::Node*& x, ir::Node*& y, Span span);

}  // namespace tex::lang
