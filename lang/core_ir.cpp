#include "lang/core_ir.h"

#include <sstream>

namespace tex::lang::ir {

const char* primName(Prim p) {
  static const char* names[] = {
      "fadd", "fsub", "fmul", "fdiv", "frem", "fneg", "fmin", "fmax", "fabs", "fsign", "ffloor",
      "fceil", "ftrunc", "fround", "fsqrt", "fexp", "fexp2", "flog", "flog2", "fsin", "fcos",
      "ftan", "fasin", "facos", "fatan", "fsinh", "fcosh", "ftanh", "fpow", "fatan2", "fstep",
      "flt", "fle", "fgt", "fge", "feq", "fne", "fisnan", "fisinf",
      "iadd", "isub", "imul", "idiv", "irem", "ineg", "iand", "ior", "ixor", "ishl", "ishr",
      "inot", "imin", "imax", "iabs", "ilt", "ile", "igt", "ige", "ieq", "ine",
      "bnot", "beq", "bne", "itof", "ftoi", "splat", "concat", "swizzle", "dot", "wavelengths",
      "mat_diffuse", "mat_emission", "mat_mix", "mat_dielectric", "mat_conductor"};
  static_assert(sizeof(names) / sizeof(names[0]) == size_t(Prim::MatConductor) + 1, "primName table out of date");
  return names[size_t(p)];
}

static void dumpNode(std::ostringstream& out, const Node* n, int indent) {
  out << std::string(size_t(indent) * 2, ' ');
  switch (n->kind) {
    case Node::Kind::Const: out << "const"; break;
    case Node::Kind::Local: out << "local %" << n->slot; break;
    case Node::Kind::Let: out << "let %" << n->slot; break;
    case Node::Kind::If: out << "if"; break;
    case Node::Kind::And: out << "and"; break;
    case Node::Kind::Or: out << "or"; break;
    case Node::Kind::Prim: out << primName(n->prim); break;
    case Node::Kind::Call: out << "call @" << n->callee; break;
    case Node::Kind::MakeRecord: out << "record"; break;
    case Node::Kind::GetField: out << "field " << n->index; break;
    case Node::Kind::Fold: out << "fold @" << n->callee; break;
  }
  if (n->kind == Node::Kind::Const) {
    if (n->type->kind == TypeKind::Int) out << " " << n->intValue;
    else if (n->type->kind == TypeKind::Bool) out << (n->boolValue ? " true" : " false");
    else out << " " << n->floatValue[0];
  }
  out << " : " << typeName(n->type) << "\n";
  for (const Node* a : n->args) dumpNode(out, a, indent + 1);
}

std::string dump(const Program& program, int function) {
  const Function& fn = program.functions[size_t(function)];
  std::ostringstream out;
  out << "fn @" << function << " " << fn.name << "(";
  for (size_t i = 0; i < fn.paramTypes.size(); ++i) out << (i ? ", " : "") << "%" << i << ": " << typeName(fn.paramTypes[i]);
  out << ") -> " << typeName(fn.resultType) << "\n";
  if (fn.body) dumpNode(out, fn.body, 1);
  return out.str();
}

}  // namespace tex::lang::ir
