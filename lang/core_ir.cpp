#include "lang/core_ir.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

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
      "mat_diffuse", "mat_emission", "mat_mix", "mat_dielectric", "mat_conductor", "mat_thin_dielectric",
      "mat_glossy", "mat_glossy_dielectric", "mat_layer", "mat_scale", "mat_add", "mat_sheen",
      "image_nearest", "image_bilinear", "image_trilinear", "image_size",
      "rgb_reflectance", "rgb_unbounded", "rgb_illuminant"};
  static_assert(sizeof(names) / sizeof(names[0]) == size_t(Prim::RgbIlluminant) + 1, "primName table out of date");
  return names[size_t(p)];
}

namespace {

struct MaterialEntry {
  Prim prim;
  const char* builtin;
  MaterialShape shape;
};

// Indexed by closure kind - 1 (kinds are 1, 2, ... in ABI order).
const MaterialEntry kMaterials[] = {
    {Prim::MatDiffuse, "diffuse", {1, 0, 1, 0, false}},
    {Prim::MatEmission, "emission", {2, 0, 1, 0, false}},
    {Prim::MatMix, "mix_material", {3, 2, 0, 0, true}},
    {Prim::MatDielectric, "dielectric", {4, 0, 2, 1, false, 3}},
    {Prim::MatConductor, "conductor", {5, 0, 2, 1, false, 3}},
    {Prim::MatThinDielectric, "thin_dielectric", {6, 0, 2, 1, false}},
    {Prim::MatGlossy, "glossy", {7, 0, 1, 1, false}},
    {Prim::MatGlossyDielectric, "glossy_dielectric", {8, 0, 1, 1, false}},
    {Prim::MatLayer, "layer", {9, 2, 0, 0, false}},
    {Prim::MatScale, "scale_material", {10, 1, 1, 0, false}},
    {Prim::MatAdd, "add_material", {11, 2, 0, 0, false}},
    {Prim::MatSheen, "sheen", {12, 0, 1, 1, false}},
};
constexpr size_t kMaterialCount = sizeof(kMaterials) / sizeof(kMaterials[0]);
static_assert(kMaterialCount == size_t(Prim::MatSheen) - size_t(Prim::MatDiffuse) + 1, "material table out of date");

}  // namespace

const MaterialShape* materialShape(Prim p) {
  if (p < Prim::MatDiffuse || p > Prim::MatSheen) return nullptr;
  return &kMaterials[size_t(p) - size_t(Prim::MatDiffuse)].shape;
}

int materialScalarCount(const Node* n, const MaterialShape& shape) {
  const size_t fixed = size_t(shape.children + shape.params + shape.scalars + (shape.weight ? 1 : 0));
  return shape.anisotropicScalars && n->args.size() == fixed - size_t(shape.scalars) + size_t(shape.anisotropicScalars)
             ? shape.anisotropicScalars
             : shape.scalars;
}

const MaterialShape* materialShapeOfKind(uint32_t kind) {
  return kind >= 1 && kind <= kMaterialCount ? &kMaterials[kind - 1].shape : nullptr;
}

const char* materialBuiltinName(uint32_t kind) {
  return kind >= 1 && kind <= kMaterialCount ? kMaterials[kind - 1].builtin : nullptr;
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

uint64_t bottomUpOverCalls(
    int function, std::map<int, uint64_t>& memo,
    const std::function<std::optional<uint64_t>(int, const std::function<std::optional<uint64_t>(int)>&)>& summarise) {
  if (auto it = memo.find(function); it != memo.end()) return it->second;
  // Functions waiting for their callees: exactly the ancestors of the one being summarised
  // (what is above one on the work stack was pushed by it or its callees).
  std::set<int> waiting;
  std::vector<int> work = {function};
  while (!work.empty()) {
    const int g = work.back();
    if (memo.count(g)) {
      work.pop_back();
      continue;
    }
    std::vector<int> missing;
    const auto callee = [&](int c) -> std::optional<uint64_t> {
      if (auto it = memo.find(c); it != memo.end()) return it->second;
      if (waiting.count(c)) return 0;  // a cycle
      missing.push_back(c);
      return std::nullopt;
    };
    const std::optional<uint64_t> value = summarise(g, callee);
    if (value && missing.empty()) {
      memo[g] = *value;
      waiting.erase(g);
      work.pop_back();
    } else {
      waiting.insert(g);
      for (int m : missing) work.push_back(m);  // computed first, then g is summarised again
    }
  }
  return memo[function];
}

uint64_t inlinedDepth(const Program& program, int function, std::map<int, uint64_t>& memo) {
  std::vector<std::pair<const Node*, uint64_t>> nodes;
  return bottomUpOverCalls(function, memo, [&](int g, const auto& callee) -> std::optional<uint64_t> {
    uint64_t deepest = 0;
    bool complete = true;
    nodes.assign(1, {program.functions[size_t(g)].body, 1});
    while (!nodes.empty()) {
      auto [n, depth] = nodes.back();
      nodes.pop_back();
      if (!n) continue;
      uint64_t here = depth;
      if (n->kind == Node::Kind::Call || n->kind == Node::Kind::Fold) {
        const std::optional<uint64_t> below = callee(n->callee);
        if (below) here = depth + *below;
        else complete = false;
      }
      deepest = std::max(deepest, here);
      for (const Node* a : n->args) nodes.push_back({a, depth + 1});
    }
    return complete ? std::optional<uint64_t>(deepest) : std::nullopt;
  });
}

}  // namespace tex::lang::ir
