// Type checking by instantiation: each definition is checked for the argument types it is
// called with, producing monomorphic core IR (docs/language.md section 4.3).
#include <algorithm>
#include <cstring>
#include <set>

#include "lang/checker_builder.h"

namespace tex::lang {

using ir::Node;
using ir::Prim;

Builder::Builder(Session::Impl& i, ModuleInfo* m)
    : impl(i), program(i.session.program()), types(TypeTable::global()), module(m) {}

Diagnostic* Builder::error(const std::string& code, Span span, std::string message, std::string help) {
  hadError_ = true;
  return impl.error(code, span, std::move(message), std::move(help));
}

// ---- node helpers ---------------------------------------------------------------------

Node* Builder::errorNode(Span span) {
  hadError_ = true;
  return program.node(Node::Kind::Const, types.error(), span);
}
Node* Builder::constFloat(float v, Span span) {
  Node* n = program.node(Node::Kind::Const, types.floating(), span);
  n->floatValue[0] = v;
  return n;
}
Node* Builder::constInt(int32_t v, Span span) {
  Node* n = program.node(Node::Kind::Const, types.integer(), span);
  n->intValue = v;
  return n;
}
Node* Builder::constBool(bool v, Span span) {
  Node* n = program.node(Node::Kind::Const, types.boolean(), span);
  n->boolValue = v;
  return n;
}
Node* Builder::constLanes(const Type* type, const float* values, Span span) {
  Node* n = program.node(Node::Kind::Const, type, span);
  std::memcpy(n->floatValue, values, sizeof(float) * type->fixedLanes());
  return n;
}
Node* Builder::prim(Prim op, const Type* type, std::vector<Node*> args, Span span) {
  Node* n = program.node(Node::Kind::Prim, type, span);
  n->prim = op;
  n->args = std::move(args);
  return n;
}
Node* Builder::local(int slot, const Type* type, Span span) {
  Node* n = program.node(Node::Kind::Local, type, span);
  n->slot = slot;
  return n;
}
Node* Builder::let(int slot, Node* value, Node* body, Span span) {
  Node* n = program.node(Node::Kind::Let, body->type, span);
  n->slot = slot;
  n->args = {value, body};
  return n;
}
Node* Builder::toFloat(Node* n, Span span) {
  if (n->type->kind != TypeKind::Int) return n;
  if (n->kind == Node::Kind::Const) return constFloat(float(n->intValue), span);
  return prim(Prim::IntToFloat, types.floating(), {n}, span);
}
Node* Builder::splatTo(Node* scalar, const Type* target, Span span) {
  scalar = toFloat(scalar, span);
  if (target == types.floating()) return scalar;
  return prim(Prim::Splat, target, {scalar}, span);
}
Node* Builder::bindOnce(Node* value, std::vector<std::pair<int, Node*>>& lets) {
  if (value->kind == Node::Kind::Local || value->kind == Node::Kind::Const) return value;
  int slot = numSlots_++;
  lets.push_back({slot, value});
  return local(slot, value->type, value->span);
}
Node* Builder::wrapLets(const std::vector<std::pair<int, Node*>>& lets, Node* body) {
  for (auto it = lets.rbegin(); it != lets.rend(); ++it) body = let(it->first, it->second, body, body->span);
  return body;
}

int Builder::declareLocal(const std::string& name, const Type* type, const Type* fnAnnotation) {
  int slot = numSlots_++;
  locals_.push_back({name, type, slot, fnAnnotation});
  return slot;
}

const LocalVar* Builder::findLocal(const std::string& name) const {
  for (auto it = locals_.rbegin(); it != locals_.rend(); ++it)
    if (it->name == name) return &*it;
  return nullptr;
}

// A value of `actual` type fits where `target` is declared without conversion: equal types,
// or callables where function types are declared (also inside records).
static bool fitsWithoutConversion(const Type* target, const Type* actual) {
  if (target == actual) return true;
  if (target->kind == TypeKind::Function) return actual->isCallable();
  if (target->kind != TypeKind::Record || actual->kind != TypeKind::Record) return false;
  if (target->fields.size() != actual->fields.size()) return false;
  for (size_t i = 0; i < target->fields.size(); ++i)
    if (target->fields[i].first != actual->fields[i].first ||
        !fitsWithoutConversion(target->fields[i].second, actual->fields[i].second))
      return false;
  return true;
}

// Promotions allowed where a type is expected: Int -> Float, Int/Float -> Spectrum.
Node* Builder::coerce(Node* n, const Type* target, Span span, const char* context) {
  if (n->type->isError() || target->isError() || fitsWithoutConversion(target, n->type)) return n;
  if (target->kind == TypeKind::Float && n->type->kind == TypeKind::Int) return toFloat(n, span);
  if (target->kind == TypeKind::Spectrum &&
      (n->type->kind == TypeKind::Int || n->type->kind == TypeKind::Float))
    return splatTo(n, target, span);
  if (target->kind == TypeKind::Function && n->type->isCallable()) return n;
  std::string message = "expected " + typeName(target) + ", found " + typeName(n->type);
  if (context) message += std::string(" ") + context;
  std::string help;
  if (target->kind == TypeKind::Color && n->type->kind == TypeKind::Vec3) help = "convert with color(v)";
  if (target->kind == TypeKind::Vec3 && n->type->kind == TypeKind::Color) help = "convert with vec3(c)";
  if (target->kind == TypeKind::Int && n->type->kind == TypeKind::Float) help = "convert with int(x) (truncates)";
  error("E0401", span, message, help);
  return errorNode(span);
}

bool unifyNumeric(Builder& b, Node*& x, Node*& y, Span span) {
  if (x->type->kind == TypeKind::Int && y->type->kind == TypeKind::Int) return true;
  Node* fx = b.toFloat(x, span);
  Node* fy = b.toFloat(y, span);
  if (!fx->type->isFloatBased() || !fy->type->isFloatBased()) return false;
  if (fx->type == fy->type) {
    x = fx, y = fy;
    return true;
  }
  if (fx->type->kind == TypeKind::Float) {
    x = b.splatTo(fx, fy->type, span), y = fy;
    return true;
  }
  if (fy->type->kind == TypeKind::Float) {
    x = fx, y = b.splatTo(fy, fx->type, span);
    return true;
  }
  return false;
}

// ---- expressions --------------------------------------------------------------------

Node* Builder::check(const Expr* e) {
  switch (e->kind) {
    case Expr::Kind::IntLit: return constInt(int32_t(e->intValue), e->span);
    case Expr::Kind::FloatLit: return constFloat(e->floatValue, e->span);
    case Expr::Kind::BoolLit: return constBool(e->boolValue, e->span);
    case Expr::Kind::StringLit:
      if (e->intValue) return errorNode(e->span);
      error("E0416", e->span, "a string literal is not a value", "strings are only the path argument of image() and image_data()");
      return errorNode(e->span);
    case Expr::Kind::Name: return checkName(e);
    case Expr::Kind::Unary: return checkUnary(e);
    case Expr::Kind::Binary: return checkBinary(e);
    case Expr::Kind::Call: return checkCall(e);
    case Expr::Kind::Field: return checkField(e);
    case Expr::Kind::Let: return checkLet(e);
    case Expr::Kind::If: return checkIf(e);
    case Expr::Kind::Lambda: return checkLambda(e);
    case Expr::Kind::Record: return checkRecord(e);
    case Expr::Kind::RecordUpdate: return checkRecordUpdate(e);
  }
  return errorNode(e->span);
}

Node* Builder::declValue(const FunctionDecl* decl, Span span) {
  if (decl->item->kind == Item::Kind::Let) {
    int idx = impl.instantiateDecl(decl, {}, span);
    if (idx < 0) return errorNode(span);
    Node* call = program.node(Node::Kind::Call, program.functions[idx].resultType, span);
    call->callee = idx;
    return call;
  }
  return program.node(Node::Kind::MakeRecord, types.funcRef(decl), span);
}

Node* Builder::checkName(const Expr* e) {
  if (const LocalVar* l = findLocal(e->name)) return local(l->slot, l->type, e->span);
  if (const Symbol* sym = lookupSymbol(module, e->name)) {
    if (sym->kind == Symbol::Kind::Decl && sym->decl) return declValue(sym->decl, e->span);
    if (sym->kind == Symbol::Kind::Module && sym->module)
      error("E0411", e->span, "'" + e->name + "' is a module, not a value", "use a member: " + e->name + ".name");
    return errorNode(e->span);  // type alias or failed import: reported already
  }
  if (isBuiltinConstant(e->name)) return builtinConstant(e->name, e->span);
  if (isBuiltinFunction(e->name)) return program.node(Node::Kind::MakeRecord, types.builtinRef(e->name), e->span);
  return errorNode(e->span);  // unknown name: reported by the resolver
}

Node* Builder::checkUnary(const Expr* e) {
  Node* x = check(e->a);
  if (x->type->isError()) return x;
  switch (e->unaryOp) {
    case UnaryOp::Neg:
      if (x->type->kind == TypeKind::Int) return prim(Prim::INeg, x->type, {x}, e->span);
      if (x->type->isFloatBased()) return prim(Prim::FNeg, x->type, {x}, e->span);
      break;
    case UnaryOp::Not:
      if (x->type->kind == TypeKind::Bool) return prim(Prim::BNot, x->type, {x}, e->span);
      break;
    case UnaryOp::BitNot:
      if (x->type->kind == TypeKind::Int) return prim(Prim::INot, x->type, {x}, e->span);
      break;
  }
  error("E0402", e->opSpan, std::string("operator '") + unaryOpText(e->unaryOp) + "' is not defined for " + typeName(x->type));
  return errorNode(e->span);
}

Node* Builder::checkBinary(const Expr* e) {
  Node* x = check(e->a);
  Node* y = check(e->b);
  if (x->type->isError() || y->type->isError()) return errorNode(e->span);
  const Type* tx = x->type;
  const Type* ty = y->type;
  auto fail = [&]() {
    std::string help;
    if ((tx->kind == TypeKind::Color && ty->isVector()) || (ty->kind == TypeKind::Color && tx->isVector()))
      help = "convert explicitly with color(v) or vec3(c)";
    else if (e->binaryOp >= BinaryOp::Eq && e->binaryOp <= BinaryOp::Ge &&
             (tx->kind == TypeKind::Spectrum || ty->kind == TypeKind::Spectrum))
      help = "a Spectrum cannot be compared (its lanes are the path's wavelengths); compare values derived from it";
    else if (tx->kind == TypeKind::Spectrum || ty->kind == TypeKind::Spectrum)
      help = "Spectrum combines with Float, Int and Spectrum only";
    error("E0402", e->opSpan,
          std::string("operator '") + binaryOpText(e->binaryOp) + "' is not defined for " + typeName(tx) + " and " + typeName(ty),
          help);
    return errorNode(e->span);
  };
  const Type* boolean = types.boolean();
  switch (e->binaryOp) {
    case BinaryOp::Or:
    case BinaryOp::And: {
      if (tx->kind != TypeKind::Bool || ty->kind != TypeKind::Bool) return fail();
      Node* n = program.node(e->binaryOp == BinaryOp::And ? Node::Kind::And : Node::Kind::Or, boolean, e->span);
      n->args = {x, y};
      return n;
    }
    case BinaryOp::Eq:
    case BinaryOp::Ne: {
      bool eq = e->binaryOp == BinaryOp::Eq;
      if (tx->kind == TypeKind::Bool && ty->kind == TypeKind::Bool)
        return prim(eq ? Prim::BEq : Prim::BNe, boolean, {x, y}, e->span);
      // A Spectrum's equality would depend on the wavelengths it is evaluated at.
      if (tx->kind == TypeKind::Spectrum || ty->kind == TypeKind::Spectrum) return fail();
      if (!unifyNumeric(*this, x, y, e->span)) return fail();
      if (x->type->kind == TypeKind::Int) return prim(eq ? Prim::IEq : Prim::INe, boolean, {x, y}, e->span);
      return prim(eq ? Prim::FEq : Prim::FNe, boolean, {x, y}, e->span);
    }
    case BinaryOp::Lt:
    case BinaryOp::Le:
    case BinaryOp::Gt:
    case BinaryOp::Ge: {
      bool scalars = (tx->kind == TypeKind::Int || tx->kind == TypeKind::Float) &&
                     (ty->kind == TypeKind::Int || ty->kind == TypeKind::Float);
      if (!scalars || !unifyNumeric(*this, x, y, e->span)) return fail();
      int k = int(e->binaryOp) - int(BinaryOp::Lt);
      static const Prim ints[] = {Prim::ILt, Prim::ILe, Prim::IGt, Prim::IGe};
      static const Prim floats[] = {Prim::FLt, Prim::FLe, Prim::FGt, Prim::FGe};
      return prim(x->type->kind == TypeKind::Int ? ints[k] : floats[k], boolean, {x, y}, e->span);
    }
    case BinaryOp::BitOr:
    case BinaryOp::BitXor:
    case BinaryOp::BitAnd:
    case BinaryOp::Shl:
    case BinaryOp::Shr: {
      if (tx->kind != TypeKind::Int || ty->kind != TypeKind::Int) return fail();
      static const Prim ops[] = {Prim::IOr, Prim::IXor, Prim::IAnd, Prim::IShl, Prim::IShr};
      return prim(ops[int(e->binaryOp) - int(BinaryOp::BitOr)], tx, {x, y}, e->span);
    }
    case BinaryOp::Add:
    case BinaryOp::Sub:
    case BinaryOp::Mul:
    case BinaryOp::Div:
    case BinaryOp::Rem: {
      if (!unifyNumeric(*this, x, y, e->span)) return fail();
      int k = int(e->binaryOp) - int(BinaryOp::Add);
      static const Prim ints[] = {Prim::IAdd, Prim::ISub, Prim::IMul, Prim::IDiv, Prim::IRem};
      static const Prim floats[] = {Prim::FAdd, Prim::FSub, Prim::FMul, Prim::FDiv, Prim::FRem};
      return prim(x->type->kind == TypeKind::Int ? ints[k] : floats[k], x->type, {x, y}, e->span);
    }
  }
  return fail();
}

std::vector<TypedArg> Builder::checkArgs(const Expr* call) {
  std::vector<TypedArg> args;
  for (const Argument& a : call->args) args.push_back({a.name, a.nameSpan, a.value->span, check(a.value)});
  return args;
}

Node* Builder::checkCall(const Expr* e) {
  const Expr* callee = e->a;
  // Named callees are resolved statically: module functions take named and default arguments.
  if (callee->kind == Expr::Kind::Name && !findLocal(callee->name)) {
    const Symbol* sym = lookupSymbol(module, callee->name);
    if (sym) {
      if (sym->kind == Symbol::Kind::Decl && sym->decl && sym->decl->item->kind == Item::Kind::Function)
        return callDecl(sym->decl, checkArgs(e), callee->span, e->span);
      if (sym->kind == Symbol::Kind::Module && sym->module) {
        error("E0408", callee->span, "'" + callee->name + "' is a module and cannot be called");
        return errorNode(e->span);
      }
      if (sym->kind == Symbol::Kind::TypeAlias) {
        error("E0408", callee->span, "'" + callee->name + "' is a type and cannot be called",
              "build records with a literal: {field: value}");
        return errorNode(e->span);
      }
    } else if (callee->name == "image" || callee->name == "image_data") {
      return imageCall(callee->name, e, callee->span);
    } else if (isBuiltinFunction(callee->name)) {
      return builtinCall(callee->name, checkArgs(e), callee->span, e->span);
    }
  }
  if (callee->kind == Expr::Kind::Field && callee->a->kind == Expr::Kind::Name && !findLocal(callee->a->name)) {
    const Symbol* sym = lookupSymbol(module, callee->a->name);
    if (sym && sym->kind == Symbol::Kind::Module) {
      const Symbol* member = sym->module ? lookupSymbol(sym->module, callee->name) : nullptr;
      if (!member || member->imported || member->kind != Symbol::Kind::Decl || !member->decl ||
          !member->decl->item->exported) {
        checkArgs(e);
        return errorNode(e->span);  // reported by the resolver
      }
      if (member->decl->item->kind == Item::Kind::Function)
        return callDecl(member->decl, checkArgs(e), callee->span, e->span);
    }
  }
  const Type* annotation = nullptr;
  if (callee->kind == Expr::Kind::Name)
    if (const LocalVar* l = findLocal(callee->name)) annotation = l->fnAnnotation;
  Node* value = check(callee);
  return apply(value, callee->span, checkArgs(e), e->span, annotation);
}

Node* Builder::callDecl(const FunctionDecl* decl, std::vector<TypedArg> args, Span calleeSpan, Span callSpan) {
  const Item& item = *decl->item;
  size_t n = item.params.size();
  std::vector<Node*> bound(n, nullptr);
  std::vector<Span> spans(n, callSpan);
  bool failed = false;
  size_t positional = 0;
  for (TypedArg& a : args) {
    if (a.node->type->isError()) failed = true;
    if (a.name.empty()) {
      if (positional >= n) {
        error("E0405", a.span,
              "too many arguments: '" + item.name + "' takes " + std::to_string(n) + " parameter" + (n == 1 ? "" : "s"));
        return errorNode(callSpan);
      }
      bound[positional] = a.node;
      spans[positional] = a.span;
      ++positional;
      continue;
    }
    size_t k = 0;
    while (k < n && item.params[k].name != a.name) ++k;
    if (k == n) {
      error("E0406", a.nameSpan, "'" + item.name + "' has no parameter named '" + a.name + "'");
      return errorNode(callSpan);
    }
    if (bound[k]) {
      error("E0407", a.nameSpan, "parameter '" + a.name + "' is given twice");
      return errorNode(callSpan);
    }
    bound[k] = a.node;
    spans[k] = a.span;
  }
  for (size_t k = 0; k < n; ++k) {
    if (bound[k]) continue;
    const Param& p = item.params[k];
    if (!p.defaultValue) {
      error("E0407", calleeSpan, "missing argument for parameter '" + p.name + "' of '" + item.name + "'");
      return errorNode(callSpan);
    }
    // Defaults are evaluated in the callee's module scope, with no locals.
    Builder inner(impl, decl->module);
    inner.numSlots_ = numSlots_;
    bound[k] = inner.check(p.defaultValue);
    numSlots_ = inner.numSlots_;
    hadError_ |= inner.hadError_;
    spans[k] = p.defaultValue->span;
  }
  if (failed) return errorNode(callSpan);
  std::vector<const Type*> argTypes;
  for (size_t k = 0; k < n; ++k) {
    if (const TypeExpr* annotation = item.params[k].type) {
      const Type* want = impl.resolveType(annotation, decl->module);
      if (want->kind == TypeKind::Function && !bound[k]->type->isCallable() && !bound[k]->type->isError()) {
        error("E0401", spans[k], "expected a function " + typeName(want) + ", found " + typeName(bound[k]->type));
        return errorNode(callSpan);
      }
      bound[k] = coerce(bound[k], want, spans[k], ("for parameter '" + item.params[k].name + "'").c_str());
    }
    if (bound[k]->type->isError()) return errorNode(callSpan);
    argTypes.push_back(bound[k]->type);
  }
  int idx = impl.instantiateDecl(decl, argTypes, calleeSpan);
  if (idx < 0 || program.functions[idx].resultType->isError()) return errorNode(callSpan);
  Node* call = program.node(Node::Kind::Call, program.functions[idx].resultType, callSpan);
  call->callee = idx;
  call->args = std::move(bound);
  return call;
}

Node* Builder::apply(Node* callee, Span calleeSpan, std::vector<TypedArg> args, Span callSpan, const Type* annotation) {
  if (callee->type->isError()) return errorNode(callSpan);
  for (auto& a : args)
    if (a.node->type->isError()) return errorNode(callSpan);
  if (callee->type->kind == TypeKind::FuncRef && !annotation)
    return callDecl(callee->type->function, std::move(args), calleeSpan, callSpan);
  for (auto& a : args) {
    if (!a.name.empty()) {
      error("E0406", a.nameSpan, "named arguments need a call of a named function",
            "pass the argument by position");
      return errorNode(callSpan);
    }
  }
  if (annotation) {
    if (args.size() != annotation->params.size()) {
      error("E0415", callSpan, "the function parameter takes " + std::to_string(annotation->params.size()) +
                                   " argument(s), " + std::to_string(args.size()) + " given");
      return errorNode(callSpan);
    }
    for (size_t i = 0; i < args.size(); ++i)
      args[i].node = coerce(args[i].node, annotation->params[i], args[i].span, "as declared by the parameter's type");
    for (auto& a : args)
      if (a.node->type->isError()) return errorNode(callSpan);
  }
  Node* result = nullptr;
  switch (callee->type->kind) {
    case TypeKind::FuncRef:
      result = callDecl(callee->type->function, std::move(args), calleeSpan, callSpan);
      break;
    case TypeKind::BuiltinRef:
      result = builtinCall(callee->type->builtin, std::move(args), calleeSpan, callSpan);
      break;
    case TypeKind::Lambda: {
      const Expr* lambda = callee->type->lambda;
      if (args.size() != lambda->params.size()) {
        error("E0415", callSpan, "this lambda takes " + std::to_string(lambda->params.size()) + " argument(s), " +
                                     std::to_string(args.size()) + " given");
        return errorNode(callSpan);
      }
      std::vector<const Type*> argTypes;
      Builder scope(impl, impl.lambdaModule[lambda]);
      for (size_t i = 0; i < args.size(); ++i) {
        if (lambda->params[i].type) {
          const Type* want = impl.resolveType(lambda->params[i].type, impl.lambdaModule[lambda]);
          args[i].node = coerce(args[i].node, want, args[i].span, "for the lambda's parameter");
          if (args[i].node->type->isError()) return errorNode(callSpan);
        }
        argTypes.push_back(args[i].node->type);
      }
      int idx = instantiateCallable(callee->type, argTypes, callSpan);
      if (idx < 0 || program.functions[idx].resultType->isError()) return errorNode(callSpan);
      Node* call = program.node(Node::Kind::Call, program.functions[idx].resultType, callSpan);
      call->callee = idx;
      call->args.push_back(callee);
      for (auto& a : args) call->args.push_back(a.node);
      result = call;
      break;
    }
    default:
      error("E0408", calleeSpan, "a value of type " + typeName(callee->type) + " is not a function and cannot be called");
      return errorNode(callSpan);
  }
  if (annotation && !result->type->isError())
    result = coerce(result, annotation->result, callSpan, "as the function parameter's declared result");
  return result;
}

// Instantiates a lambda type for argument types: a function (closure, params...).
int Builder::instantiateCallable(const Type* callable, const std::vector<const Type*>& args, Span at) {
  if (callable->kind == TypeKind::FuncRef) return impl.instantiateDecl(callable->function, args, at);
  const Expr* lambda = callable->lambda;
  if (args.size() != lambda->params.size()) {
    error("E0415", at, "this lambda takes " + std::to_string(lambda->params.size()) + " argument(s), " +
                           std::to_string(args.size()) + " given");
    return -1;
  }
  auto key = std::make_pair(static_cast<const void*>(callable), args);
  if (auto it = impl.instances.find(key); it != impl.instances.end()) {
    // An instance still being checked (no result type yet) is asked for again: the lambda
    // calls itself through an argument (`(|f| f(f))(|f| f(f))`), recursion the resolver
    // cannot see by name. Its unfinished function must not be used.
    if (!program.functions[size_t(it->second)].resultType) {
      error("E0307", at, "this lambda is called recursively (through an argument)", "recursion is not allowed");
      return -1;
    }
    return it->second;
  }
  if (++impl.genericInstances > impl.maxInstances() || impl.instanceDepth > 200) {
    error("E0413", at, "specialisation limit exceeded: too many or too deeply nested function instances");
    return -1;
  }
  int idx = int(program.functions.size());
  program.functions.emplace_back();
  program.functions[idx].name = "<lambda>";
  program.functions[idx].span = lambda->span;
  impl.instances[key] = idx;
  ++impl.instanceDepth;
  Builder body(impl, impl.lambdaModule[lambda]);
  int closureSlot = body.declareLocal("", callable);
  std::vector<const Type*> paramTypes = {callable};
  for (size_t i = 0; i < args.size(); ++i) {
    const Type* fnAnnotation = nullptr;
    if (lambda->params[i].type) {
      const Type* t = impl.resolveType(lambda->params[i].type, body.module);
      if (t->kind == TypeKind::Function) fnAnnotation = t;
    }
    body.declareLocal(lambda->params[i].name, args[i], fnAnnotation);
    paramTypes.push_back(args[i]);
  }
  std::vector<std::pair<int, Node*>> captures;
  for (size_t k = 0; k < callable->fields.size(); ++k) {
    Node* get = program.node(Node::Kind::GetField, callable->fields[k].second, lambda->span);
    get->index = int(k);
    get->args = {body.local(closureSlot, callable, lambda->span)};
    const Type* fnAnnotation = nullptr;
    if (auto it = impl.captureAnnotations.find({lambda, callable->fields[k].first}); it != impl.captureAnnotations.end())
      fnAnnotation = it->second;
    int slot = body.declareLocal(callable->fields[k].first, callable->fields[k].second, fnAnnotation);
    captures.push_back({slot, get});
  }
  Node* result = body.wrapLets(captures, body.check(lambda->a));
  --impl.instanceDepth;
  ir::Function& fn = program.functions[idx];
  fn.paramTypes = paramTypes;
  fn.resultType = result->type;
  fn.body = result;
  fn.numSlots = body.numSlots();
  return idx;
}

Node* Builder::checkField(const Expr* e) {
  if (e->a->kind == Expr::Kind::Name && !findLocal(e->a->name)) {
    const Symbol* sym = lookupSymbol(module, e->a->name);
    if (sym && sym->kind == Symbol::Kind::Module) {
      const Symbol* member = sym->module ? lookupSymbol(sym->module, e->name) : nullptr;
      if (!member || member->imported || member->kind != Symbol::Kind::Decl || !member->decl ||
          !member->decl->item->exported)
        return errorNode(e->span);  // reported by the resolver
      return declValue(member->decl, e->span);
    }
  }
  Node* base = check(e->a);
  const Type* t = base->type;
  if (t->isError()) return base;
  if (t->kind == TypeKind::Record) {
    for (size_t i = 0; i < t->fields.size(); ++i) {
      if (t->fields[i].first != e->name) continue;
      Node* n = program.node(Node::Kind::GetField, t->fields[i].second, e->span);
      n->index = int(i);
      n->args = {base};
      return n;
    }
    std::string names;
    for (auto& f : t->fields) names += (names.empty() ? "" : ", ") + f.first;
    error("E0409", e->nameSpan, "no field '" + e->name + "' in " + typeName(t), "its fields are: " + names);
    return errorNode(e->span);
  }
  if (t->isVector() || t->kind == TypeKind::Color) return swizzle(base, e->name, e->nameSpan);
  error("E0409", e->nameSpan, "a value of type " + typeName(t) + " has no field '" + e->name + "'");
  return errorNode(e->span);
}

Node* Builder::swizzle(Node* base, const std::string& letters, Span span) {
  const Type* t = base->type;
  bool isColor = t->kind == TypeKind::Color;
  const char* alphabet = isColor ? "rgb" : "xyzw";
  int size = t->fixedLanes();
  std::vector<uint8_t> lanes;
  for (char c : letters) {
    const char* p = std::strchr(alphabet, c);
    if (!p || int(p - alphabet) >= size || c == 0) {
      lanes.clear();
      break;
    }
    lanes.push_back(uint8_t(p - alphabet));
  }
  if (lanes.empty() || lanes.size() > 4) {
    error("E0409", span, "no component '" + letters + "' in " + typeName(t),
          isColor ? "Color components are r, g, b" : std::string("components of ") + typeName(t) + " are " +
                                                         std::string(alphabet, size_t(size)));
    return errorNode(span);
  }
  Node* n = prim(Prim::Swizzle, types.vec(int(lanes.size())), {base}, span);
  n->lanes = std::move(lanes);
  return n;
}

Node* Builder::checkLet(const Expr* e) {
  Node* value = check(e->a);
  if (e->annotation) {
    const Type* want = impl.resolveType(e->annotation, module);
    value = coerce(value, want, e->a->span, ("for '" + e->name + "'").c_str());
  }
  const Type* fnAnnotation = nullptr;
  if (e->annotation) {
    const Type* t = impl.resolveType(e->annotation, module);
    if (t->kind == TypeKind::Function) fnAnnotation = t;
  }
  int slot = declareLocal(e->name, value->type, fnAnnotation);
  Node* body = check(e->b);
  popLocals(1);
  return let(slot, value, body, e->span);
}

Node* Builder::checkIf(const Expr* e) {
  Node* cond = check(e->a);
  if (!cond->type->isError() && cond->type->kind != TypeKind::Bool) {
    error("E0403", e->a->span, "the condition of 'if' must be Bool, found " + typeName(cond->type),
          cond->type->kind == TypeKind::Int || cond->type->kind == TypeKind::Float ? "compare explicitly, e.g. x != 0" : "");
    cond = errorNode(e->a->span);
  }
  Node* yes = check(e->b);
  Node* no = check(e->c);
  if (cond->type->isError() || yes->type->isError() || no->type->isError()) return errorNode(e->span);
  if (yes->type != no->type) {
    bool numeric = (yes->type->kind == TypeKind::Int || yes->type->kind == TypeKind::Float) &&
                   (no->type->kind == TypeKind::Int || no->type->kind == TypeKind::Float);
    if (!numeric) {
      Diagnostic* d = error("E0404", e->c->span,
                            "the branches of 'if' have different types: " + typeName(yes->type) + " and " + typeName(no->type));
      if (d) d->notes.push_back({e->b->span, "the first branch is " + typeName(yes->type)});
      return errorNode(e->span);
    }
    yes = toFloat(yes, e->b->span);
    no = toFloat(no, e->c->span);
  }
  Node* n = program.node(Node::Kind::If, yes->type, e->span);
  n->args = {cond, yes, no};
  return n;
}

// Free names of a lambda body that are not bound inside it, in first-use order.
static void freeNames(const Expr* e, std::vector<std::string>& bound, std::vector<std::string>& out) {
  if (!e) return;
  auto isBound = [&](const std::string& n) { return std::find(bound.begin(), bound.end(), n) != bound.end(); };
  switch (e->kind) {
    case Expr::Kind::Name:
      if (!isBound(e->name) && std::find(out.begin(), out.end(), e->name) == out.end()) out.push_back(e->name);
      return;
    case Expr::Kind::Let:
      freeNames(e->a, bound, out);
      bound.push_back(e->name);
      freeNames(e->b, bound, out);
      bound.pop_back();
      return;
    case Expr::Kind::Lambda:
      for (auto& p : e->params) bound.push_back(p.name);
      freeNames(e->a, bound, out);
      bound.resize(bound.size() - e->params.size());
      return;
    default:
      freeNames(e->a, bound, out);
      freeNames(e->b, bound, out);
      freeNames(e->c, bound, out);
      for (auto& a : e->args) freeNames(a.value, bound, out);
      for (auto& f : e->fields) freeNames(f.value, bound, out);
      return;
  }
}

Node* Builder::checkLambda(const Expr* e) {
  std::vector<std::string> bound, names;
  for (auto& p : e->params) bound.push_back(p.name);
  freeNames(e->a, bound, names);
  std::vector<std::pair<std::string, const Type*>> captures;
  std::vector<Node*> values;
  for (const std::string& n : names) {
    const LocalVar* l = findLocal(n);
    if (!l || l->name.empty()) continue;
    captures.push_back({n, l->type});
    values.push_back(local(l->slot, l->type, e->span));
    // A captured parameter keeps its function-type annotation inside the lambda.
    if (l->fnAnnotation) impl.captureAnnotations[{e, n}] = l->fnAnnotation;
  }
  impl.lambdaModule[e] = module;
  Node* n = program.node(Node::Kind::MakeRecord, types.lambda(e, captures), e->span);
  n->args = std::move(values);
  return n;
}

Node* Builder::checkRecord(const Expr* e) {
  std::vector<std::pair<std::string, Node*>> fields;
  bool failed = false;
  for (const FieldInit& f : e->fields) {
    Node* v = check(f.value);
    failed |= v->type->isError();
    fields.push_back({f.name, v});
  }
  if (failed) return errorNode(e->span);
  std::sort(fields.begin(), fields.end(), [](auto& a, auto& b) { return a.first < b.first; });
  std::vector<std::pair<std::string, const Type*>> fieldTypes;
  Node* n = program.node(Node::Kind::MakeRecord, nullptr, e->span);
  for (auto& [name, v] : fields) {
    fieldTypes.push_back({name, v->type});
    n->args.push_back(v);
  }
  n->type = types.record(fieldTypes);
  return n;
}

Node* Builder::checkRecordUpdate(const Expr* e) {
  Node* base = check(e->a);
  if (base->type->isError()) return base;
  const Type* t = base->type;
  if (t->kind != TypeKind::Record) {
    error("E0409", e->a->span, "'with' needs a record, found " + typeName(t));
    return errorNode(e->span);
  }
  std::vector<std::pair<int, Node*>> lets;
  Node* baseLocal = bindOnce(base, lets);
  std::vector<Node*> values(t->fields.size(), nullptr);
  for (const FieldInit& f : e->fields) {
    size_t i = 0;
    while (i < t->fields.size() && t->fields[i].first != f.name) ++i;
    if (i == t->fields.size()) {
      error("E0409", f.nameSpan, "no field '" + f.name + "' in " + typeName(t), "'with' can only replace existing fields");
      return errorNode(e->span);
    }
    values[i] = coerce(check(f.value), t->fields[i].second, f.value->span, ("for field '" + f.name + "'").c_str());
    if (values[i]->type->isError()) return errorNode(e->span);
  }
  Node* n = program.node(Node::Kind::MakeRecord, t, e->span);
  for (size_t i = 0; i < t->fields.size(); ++i) {
    if (!values[i]) {
      values[i] = program.node(Node::Kind::GetField, t->fields[i].second, e->span);
      values[i]->index = int(i);
      values[i]->args = {baseLocal};
    }
    n->args.push_back(values[i]);
  }
  return wrapLets(lets, n);
}

// ---- instances and module-level checks ----------------------------------------------------

int Session::Impl::instantiateDecl(const FunctionDecl* decl, const std::vector<const Type*>& args, Span at) {
  auto key = std::make_pair(static_cast<const void*>(decl), args);
  if (auto it = instances.find(key); it != instances.end()) {
    if (it->second == -2) {
      error("E0307", at, "'" + decl->item->name + "' is used recursively", "recursion is not allowed");
      return -1;
    }
    return it->second;
  }
  ir::Program& program = session.program();
  if (instanceDepth == 0) genericInstances = 0;  // the limit is per top-level request
  // Only instances of generic definitions can multiply; annotated ones exist once each.
  bool generic = false;
  for (const Param& p : decl->item->params) generic |= !p.type;
  if ((generic && ++genericInstances > session.options_.maxInstances) || instanceDepth > 200) {
    error("E0413", at, "specialisation limit exceeded while instantiating '" + decl->item->name + "'",
          "too many distinct instances of generic functions or lambdas (limit " +
              std::to_string(session.options_.maxInstances) + ")");
    return -1;
  }
  instances[key] = -2;
  ++instanceDepth;
  size_t diagnosticsBefore = session.diags().size();
  Builder body(*this, decl->module);
  const Item& item = *decl->item;
  std::vector<const Type*> paramTypes;
  for (size_t i = 0; i < item.params.size() && i < args.size(); ++i) {
    const Type* fnAnnotation = nullptr;
    if (item.params[i].type) {
      const Type* t = resolveType(item.params[i].type, decl->module);
      if (t->kind == TypeKind::Function) fnAnnotation = t;
    }
    body.declareLocal(item.params[i].name, args[i], fnAnnotation);
    paramTypes.push_back(args[i]);
  }
  ir::Node* result = body.check(item.body);
  if (item.resultType) {
    const Type* want = resolveType(item.resultType, decl->module);
    if (want->kind == TypeKind::Function) {
      if (!result->type->isCallable() && !result->type->isError())
        body.error("E0401", item.body->span, "expected a function " + typeName(want) + ", found " + typeName(result->type));
    } else {
      result = body.coerce(result, want, item.body->span, "as the declared result");
    }
  }
  bool declaresCallable = item.resultType && resolveType(item.resultType, decl->module)->containsCallable();
  if (item.exported && (declaresCallable || result->type->containsCallable()) && !result->type->isError()) {
    body.error("E0411", item.resultType ? item.resultType->span : item.nameSpan, "exported '" + item.name + "' returns a function value",
               "exported definitions are called by the renderer and must return plain data");
  }
  --instanceDepth;
  // Errors inside a generic instance also point at the call that asked for it.
  if (at.file && at.begin != item.nameSpan.begin) {
    for (size_t i = diagnosticsBefore; i < session.diags().size(); ++i) {
      Diagnostic& d = session.diags().at(i);
      if (d.notes.size() < 4) d.notes.push_back({at, "in '" + decl->item->name + "' as called here"});
    }
  }
  int idx = int(program.functions.size());
  ir::Function fn;
  std::string name = decl->qualifiedName();
  if (!args.empty()) {
    name += "<";
    for (size_t i = 0; i < args.size(); ++i) name += (i ? ", " : "") + typeName(args[i]);
    name += ">";
  }
  fn.name = name;
  fn.span = item.nameSpan;
  fn.paramTypes = paramTypes;
  fn.resultType = result->type;
  fn.body = result;
  fn.numSlots = body.numSlots();
  program.functions.push_back(std::move(fn));
  instances[key] = idx;
  return idx;
}

void Session::Impl::checkEagerly(ModuleInfo* module, Module& ast) {
  for (const Item& item : ast.items) {
    if (item.kind == Item::Kind::Type) continue;
    const Symbol* sym = lookupSymbol(module, item.name);
    if (!sym || sym->kind != Symbol::Kind::Decl || !sym->decl || sym->decl->item != &item) continue;
    std::vector<const Type*> args;
    bool annotated = true;
    for (const Param& p : item.params) {
      if (!p.type) {
        annotated = false;
        break;
      }
      args.push_back(resolveType(p.type, module));
    }
    if (!annotated) continue;  // generic: checked per instance at its call sites
    bool hasFunctionParam = false;
    for (const Type* t : args) hasFunctionParam |= t->kind == TypeKind::Function || t->isError();
    if (hasFunctionParam) continue;  // specialised per callable at its call sites
    instantiateDecl(sym->decl, args, item.nameSpan);
  }
}

int Session::Impl::compileExpression(ModuleInfo* scope, const Expr* expr,
                                     const std::vector<std::pair<std::string, const Type*>>& params) {
  ir::Program& program = session.program();
  genericInstances = 0;  // the limit is per top-level request
  Builder body(*this, scope);
  std::vector<const Type*> paramTypes;
  for (auto& [name, type] : params) {
    body.declareLocal(name, type);
    paramTypes.push_back(type);
  }
  size_t before = session.diags().size();
  ir::Node* result = body.check(expr);
  if (session.diags().size() != before || result->type->isError()) return -1;
  ir::Function fn;
  fn.name = "<expression>";
  fn.span = expr->span;
  fn.paramTypes = paramTypes;
  fn.resultType = result->type;
  fn.body = result;
  fn.numSlots = body.numSlots();
  program.functions.push_back(std::move(fn));
  return int(program.functions.size()) - 1;
}

const Type* Session::Impl::resolveType(const TypeExpr* t, ModuleInfo* module, int depth) {
  TypeTable& types = TypeTable::global();
  if (depth > 64) {
    error("E0310", t->span, "type alias refers to itself");
    return types.error();
  }
  switch (t->kind) {
    case TypeExpr::Kind::Name: {
      static const std::map<std::string, TypeKind> builtin = {
          {"Bool", TypeKind::Bool},   {"Int", TypeKind::Int},     {"Float", TypeKind::Float},
          {"Vec2", TypeKind::Vec2},   {"Vec3", TypeKind::Vec3},   {"Vec4", TypeKind::Vec4},
          {"Color", TypeKind::Color}, {"Spectrum", TypeKind::Spectrum}, {"Material", TypeKind::Material}, {"Image", TypeKind::Image}};
      if (const Symbol* sym = lookupSymbol(module, t->name)) {
        if (sym->kind == Symbol::Kind::TypeAlias) {
          // A cycle is reported where it closes, at once: `type S = (S) -> S` used to be
          // expanded to depth 64 along both the parameter and the result (2^64 steps).
          const void* alias = sym->typeItem;
          if (std::find(resolvingAliases.begin(), resolvingAliases.end(), alias) != resolvingAliases.end()) {
            error("E0310", t->span, "type alias '" + t->name + "' refers to itself");
            return types.error();
          }
          resolvingAliases.push_back(alias);
          const Type* resolved = resolveType(sym->typeItem->resultType, sym->owner, depth + 1);
          resolvingAliases.pop_back();
          return resolved;
        }
        if (sym->kind == Symbol::Kind::Decl && !sym->decl) return types.error();  // failed import
      }
      if (auto it = builtin.find(t->name); it != builtin.end()) return types.basic(it->second);
      if (t->name == "Hit") return types.hit();
      error("E0310", t->span, "unknown type '" + t->name + "'",
            "types are Bool, Int, Float, Vec2, Vec3, Vec4, Color, Spectrum, Material, Image, Hit, records and aliases");
      return types.error();
    }
    case TypeExpr::Kind::Record: {
      std::vector<std::pair<std::string, const Type*>> fields;
      for (auto& [name, ft] : t->fields) {
        const Type* resolved = resolveType(ft, module, depth + 1);
        if (resolved->isError()) return resolved;
        fields.push_back({name, resolved});
      }
      return types.record(fields);
    }
    case TypeExpr::Kind::Function: {
      std::vector<const Type*> params;
      for (auto* p : t->params) {
        params.push_back(resolveType(p, module, depth + 1));
        if (params.back()->isError()) return params.back();
      }
      const Type* result = resolveType(t->result, module, depth + 1);
      if (result->isError()) return result;
      return types.function(params, result);
    }
  }
  return types.error();
}

}  // namespace tex::lang
