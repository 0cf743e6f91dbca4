// The prelude's builtins (docs/language.md section 6): typing, and their expansion into
// core IR primitives. Composite builtins (mix, smoothstep, normalize, ...) are expanded here
// so the IR, the interpreter and the compiler only know a small set of primitives.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "lang/checker_builder.h"
#include "lang/image_table.h"

namespace tex::lang {

using ir::Node;
using ir::Prim;

namespace {

const std::map<std::string, Prim>& unaryFloatBuiltins() {
  static const std::map<std::string, Prim> table = {
      {"sign", Prim::FSign}, {"floor", Prim::FFloor}, {"ceil", Prim::FCeil}, {"trunc", Prim::FTrunc},
      {"round", Prim::FRound}, {"sqrt", Prim::FSqrt}, {"exp", Prim::FExp}, {"exp2", Prim::FExp2},
      {"log", Prim::FLog}, {"log2", Prim::FLog2}, {"sin", Prim::FSin}, {"cos", Prim::FCos},
      {"tan", Prim::FTan}, {"asin", Prim::FAsin}, {"acos", Prim::FAcos}, {"atan", Prim::FAtan},
      {"sinh", Prim::FSinh}, {"cosh", Prim::FCosh}, {"tanh", Prim::FTanh}};
  return table;
}

const std::set<std::string>& otherBuiltins() {
  static const std::set<std::string> names = {
      "abs", "fract", "min", "max", "clamp", "pow", "atan2", "mod", "mix", "step", "smoothstep",
      "dot", "length", "distance", "normalize", "cross", "float", "int", "is_nan", "is_inf",
      "vec2", "vec3", "vec4", "rgb", "color", "luminance", "spectrum", "fold", "diffuse",
      "emission", "mix_material", "dielectric", "conductor", "thin_dielectric", "glossy", "glossy_dielectric",
      "layer", "scale_material", "add_material", "sheen", "image", "image_data", "image_size", "sample", "sample_nearest",
      "sample_alpha", "sample_filtered", "reflectance_spectrum", "unbounded_spectrum", "illuminant_spectrum"};
  return names;
}

// Builtins whose parameters may also be given by name (`dielectric(ior: 1.5)`), with the
// defaults of the optional ones (which may be left out also when arguments are positional).
const std::map<std::string, std::vector<BuiltinParam>>& namedBuiltinParams() {
  static const BuiltinParam roughness{"roughness", true, 0.0f};
  static const BuiltinParam rotation{"rotation", true, 0.0f};  // of an anisotropic (Vec2) roughness's axes
  static const std::map<std::string, std::vector<BuiltinParam>> table = {
      {"dielectric", {{"ior"}, roughness, {"transmission_tint", true, 1.0f}, rotation}},
      {"conductor", {{"eta"}, {"k"}, roughness, rotation}},
      {"thin_dielectric", {{"ior"}, roughness, {"transmission_tint", true, 1.0f}}},
      {"glossy", {{"reflectance"}, {"n"}}},
      {"glossy_dielectric", {{"ior"}, {"n"}}},
      {"layer", {{"coat"}, {"base"}}},
      {"scale_material", {{"m"}, {"w"}}},
      {"add_material", {{"a"}, {"b"}}},
      {"sheen", {{"color"}, {"roughness"}}},
      {"mix_material", {{"a"}, {"b"}, {"t"}}}};
  return table;
}

}  // namespace

bool isBuiltinFunction(const std::string& name) {
  return unaryFloatBuiltins().count(name) || otherBuiltins().count(name);
}

bool isBuiltinConstant(const std::string& name) {
  return name == "pi" || name == "tau" || name == "inf" || name == "nan" || name == "lambda_nm" || name == "wrap_repeat" ||
         name == "wrap_clamp" || name == "wrap_mirror";
}

Node* Builder::builtinConstant(const std::string& name, Span span) {
  if (name == "pi") return constFloat(3.14159265358979323846f, span);
  if (name == "tau") return constFloat(6.28318530717958647692f, span);
  if (name == "inf") return constFloat(std::numeric_limits<float>::infinity(), span);
  if (name == "nan") return constFloat(std::numeric_limits<float>::quiet_NaN(), span);
  if (name == "wrap_repeat") return constInt(int32_t(ImageWrap::Repeat), span);
  if (name == "wrap_clamp") return constInt(int32_t(ImageWrap::Clamp), span);
  if (name == "wrap_mirror") return constInt(int32_t(ImageWrap::Mirror), span);
  return prim(Prim::Wavelengths, types.spectrum(), {}, span);  // lambda_nm
}

// Puts named arguments in parameter order (positional ones come first: the parser checks it)
// and fills in the defaults of optional parameters left out. Returns false after reporting
// E0406 (unknown name) or E0407 (repeated or missing).
bool Builder::orderBuiltinArgs(const std::string& name, const std::vector<BuiltinParam>& params,
                               std::vector<TypedArg>& args, Span calleeSpan, Span callSpan) {
  std::vector<const TypedArg*> slots(std::max(params.size(), args.size()), nullptr);
  for (size_t i = 0; i < args.size(); ++i) {
    const TypedArg& a = args[i];
    if (a.name.empty()) {
      slots[i] = &a;
      continue;
    }
    size_t at = size_t(std::find_if(params.begin(), params.end(), [&](const BuiltinParam& p) { return p.name == a.name; }) -
                       params.begin());
    if (at == params.size()) {
      error("E0406", a.nameSpan, "builtin '" + name + "' has no parameter named '" + a.name + "'");
      return false;
    }
    if (slots[at]) {
      error("E0407", a.nameSpan, "parameter '" + a.name + "' is given twice");
      return false;
    }
    slots[at] = &a;
  }
  std::vector<TypedArg> ordered;
  for (size_t i = 0; i < slots.size(); ++i) {
    if (!slots[i]) {
      if (i < params.size() && params[i].optional) {
        ordered.push_back(TypedArg{"", callSpan, callSpan, constFloat(params[i].value, callSpan)});
        continue;
      }
      error("E0407", calleeSpan, "missing argument for parameter '" + params[i].name + "' of '" + name + "'");
      return false;
    }
    ordered.push_back(*slots[i]);
    ordered.back().name.clear();
  }
  args = std::move(ordered);
  return true;
}

Node* Builder::builtinCall(const std::string& name, std::vector<TypedArg> args, Span calleeSpan, Span callSpan) {
  if (auto it = namedBuiltinParams().find(name); it != namedBuiltinParams().end()) {
    bool anyNamed = std::any_of(args.begin(), args.end(), [](const TypedArg& a) { return !a.name.empty(); });
    // Positional calls that leave out only optional parameters get their defaults too; other
    // arities are left to the overload check below (E0410).
    size_t required = size_t(std::count_if(it->second.begin(), it->second.end(), [](const BuiltinParam& p) { return !p.optional; }));
    bool fillDefaults = !anyNamed && args.size() >= required && args.size() < it->second.size();
    if ((anyNamed || fillDefaults) && !orderBuiltinArgs(name, it->second, args, calleeSpan, callSpan))
      return errorNode(callSpan);
  }
  for (auto& a : args) {
    if (a.node->type->isError()) return errorNode(callSpan);
    if (!a.name.empty()) {
      error("E0406", a.nameSpan, "builtin '" + name + "' takes no named arguments", "pass arguments by position");
      return errorNode(callSpan);
    }
  }
  auto noOverload = [&](const char* expected) {
    std::string got;
    for (auto& a : args) got += (got.empty() ? "" : ", ") + typeName(a.node->type);
    error("E0410", calleeSpan, "no overload of '" + name + "' takes (" + got + ")", std::string("expected ") + expected);
    return errorNode(callSpan);
  };
  auto arity = [&](size_t n) { return args.size() == n; };
  auto kind = [&](size_t i) { return args[i].node->type->kind; };
  auto isNumeric = [&](size_t i) { return kind(i) == TypeKind::Int || args[i].node->type->isFloatBased(); };
  std::vector<std::pair<int, Node*>> lets;

  if (auto it = unaryFloatBuiltins().find(name); it != unaryFloatBuiltins().end()) {
    if (!arity(1) || !isNumeric(0)) return noOverload("one Float, vector, Color or Spectrum");
    Node* x = toFloat(args[0].node, callSpan);
    return prim(it->second, x->type, {x}, callSpan);
  }
  if (name == "abs") {
    if (!arity(1) || !isNumeric(0)) return noOverload("one Int, Float, vector, Color or Spectrum");
    Node* x = args[0].node;
    return prim(kind(0) == TypeKind::Int ? Prim::IAbs : Prim::FAbs, x->type, {x}, callSpan);
  }
  if (name == "fract") {
    if (!arity(1) || !isNumeric(0)) return noOverload("one Float, vector, Color or Spectrum");
    // x - floor(x), kept below 1: for tiny negative x the subtraction rounds up to exactly 1
    // (fract(-1e-9) would be 1.0), outside the [0, 1) every user of fract counts on. Branch-free
    // and lane-wise: min(r, 1 - 2^-24) + (r - r), where r - r is 0 for finite r and NaN for
    // NaN or inf (min alone would turn a NaN into 1 - 2^-24).
    Node* x = bindOnce(toFloat(args[0].node, callSpan), lets);
    Node* r = bindOnce(prim(Prim::FSub, x->type, {x, prim(Prim::FFloor, x->type, {x}, callSpan)}, callSpan), lets);
    Node* belowOne = splatTo(constFloat(0x1.fffffep-1f, callSpan), x->type, callSpan);
    return wrapLets(lets, prim(Prim::FAdd, x->type, {prim(Prim::FMin, x->type, {r, belowOne}, callSpan), prim(Prim::FSub, x->type, {r, r}, callSpan)}, callSpan));
  }
  if (name == "min" || name == "max" || name == "pow" || name == "atan2" || name == "mod") {
    if (!arity(2) || !isNumeric(0) || !isNumeric(1)) return noOverload("two numeric arguments");
    Node* x = args[0].node;
    Node* y = args[1].node;
    bool ints = kind(0) == TypeKind::Int && kind(1) == TypeKind::Int;
    if (ints && (name == "min" || name == "max"))
      return prim(name == "min" ? Prim::IMin : Prim::IMax, x->type, {x, y}, callSpan);
    x = toFloat(x, callSpan);
    y = toFloat(y, callSpan);
    if (!unifyNumeric(*this, x, y, callSpan)) return noOverload("arguments of one type (or a scalar and a vector)");
    if (name == "min") return prim(Prim::FMin, x->type, {x, y}, callSpan);
    if (name == "max") return prim(Prim::FMax, x->type, {x, y}, callSpan);
    if (name == "pow") return prim(Prim::FPow, x->type, {x, y}, callSpan);
    if (name == "atan2") return prim(Prim::FAtan2, x->type, {x, y}, callSpan);
    // mod(x, y) = x - y * floor(x / y)
    x = bindOnce(x, lets);
    y = bindOnce(y, lets);
    const Type* t = x->type;
    Node* q = prim(Prim::FFloor, t, {prim(Prim::FDiv, t, {x, y}, callSpan)}, callSpan);
    return wrapLets(lets, prim(Prim::FSub, t, {x, prim(Prim::FMul, t, {y, q}, callSpan)}, callSpan));
  }
  if (name == "clamp") {
    if (!arity(3) || !isNumeric(0) || !isNumeric(1) || !isNumeric(2)) return noOverload("(x, lo, hi)");
    Node* x = args[0].node;
    Node* lo = args[1].node;
    Node* hi = args[2].node;
    if (kind(0) == TypeKind::Int && kind(1) == TypeKind::Int && kind(2) == TypeKind::Int)
      return prim(Prim::IMin, x->type, {prim(Prim::IMax, x->type, {x, lo}, callSpan), hi}, callSpan);
    x = toFloat(x, callSpan);
    if (!unifyNumeric(*this, x, lo, callSpan) || !unifyNumeric(*this, x, hi, callSpan) || lo->type != hi->type)
      return noOverload("(x, lo, hi) of one type, or scalar bounds");
    return prim(Prim::FMin, x->type, {prim(Prim::FMax, x->type, {x, lo}, callSpan), hi}, callSpan);
  }
  if (name == "mix") {
    if (!arity(3) || !isNumeric(0) || !isNumeric(1) || !isNumeric(2)) return noOverload("(a, b, t)");
    Node* a = toFloat(args[0].node, callSpan);
    Node* b = toFloat(args[1].node, callSpan);
    Node* t = toFloat(args[2].node, callSpan);
    if (!unifyNumeric(*this, a, b, callSpan)) return noOverload("a and b of one type");
    if (t->type != a->type) {
      if (t->type->kind != TypeKind::Float) return noOverload("t a Float or of the type of a and b");
      t = splatTo(t, a->type, callSpan);
    }
    const Type* ty = a->type;
    a = bindOnce(a, lets);
    // a + (b - a) * t
    Node* d = prim(Prim::FSub, ty, {b, a}, callSpan);
    return wrapLets(lets, prim(Prim::FAdd, ty, {a, prim(Prim::FMul, ty, {d, t}, callSpan)}, callSpan));
  }
  if (name == "step") {
    if (!arity(2) || !isNumeric(0) || !isNumeric(1)) return noOverload("(edge, x)");
    Node* edge = toFloat(args[0].node, callSpan);
    Node* x = toFloat(args[1].node, callSpan);
    if (!unifyNumeric(*this, edge, x, callSpan)) return noOverload("edge and x of one type, or a scalar edge");
    return prim(Prim::FStep, x->type, {edge, x}, callSpan);
  }
  if (name == "smoothstep") {
    if (!arity(3) || !isNumeric(0) || !isNumeric(1) || !isNumeric(2)) return noOverload("(e0, e1, x)");
    Node* e0 = toFloat(args[0].node, callSpan);
    Node* e1 = toFloat(args[1].node, callSpan);
    Node* x = toFloat(args[2].node, callSpan);
    if (!unifyNumeric(*this, x, e0, callSpan) || !unifyNumeric(*this, x, e1, callSpan) || e0->type != e1->type)
      return noOverload("edges of the type of x, or scalar edges");
    const Type* ty = x->type;
    e0 = bindOnce(e0, lets);
    // t = clamp((x - e0) / (e1 - e0), 0, 1); t * t * (3 - 2 t)
    Node* ratio = prim(Prim::FDiv, ty, {prim(Prim::FSub, ty, {x, e0}, callSpan), prim(Prim::FSub, ty, {e1, e0}, callSpan)}, callSpan);
    Node* t = prim(Prim::FMin, ty, {prim(Prim::FMax, ty, {ratio, splatTo(constFloat(0, callSpan), ty, callSpan)}, callSpan),
                                    splatTo(constFloat(1, callSpan), ty, callSpan)}, callSpan);
    t = bindOnce(t, lets);
    Node* poly = prim(Prim::FSub, ty, {splatTo(constFloat(3, callSpan), ty, callSpan),
                                       prim(Prim::FMul, ty, {splatTo(constFloat(2, callSpan), ty, callSpan), t}, callSpan)}, callSpan);
    return wrapLets(lets, prim(Prim::FMul, ty, {prim(Prim::FMul, ty, {t, t}, callSpan), poly}, callSpan));
  }
  auto isVectorLike = [&](size_t i) { return args[i].node->type->isVector() || kind(i) == TypeKind::Color; };
  // |v| without overflow or underflow: sqrt(v.v) when v.v is a normal float (almost always),
  // else (v.v overflowed, or is subnormal or 0) m |v / m| with m the largest |component|, as
  // hypot does; so length(vec3(1e20, 0, 0)) is 1e20, not inf, and normalize of tiny or huge
  // vectors is unit length. Zero, inf and NaN components still give 0, inf and NaN.
  auto safeLength = [&](Node* v) -> Node* {
    const Type* f = types.floating();
    Node* d = bindOnce(prim(Prim::Dot, f, {v, v}, callSpan), lets);
    Node* normal = program.node(Node::Kind::And, types.boolean(), callSpan);
    normal->args = {prim(Prim::FGe, types.boolean(), {d, constFloat(1.17549435e-38f, callSpan)}, callSpan),
                    prim(Prim::FLt, types.boolean(), {d, constFloat(std::numeric_limits<float>::infinity(), callSpan)}, callSpan)};
    const int lanes = v->type->fixedLanes();
    Node* largest = nullptr;
    for (int i = 0; i < lanes; ++i) {
      Node* c = prim(Prim::Swizzle, f, {v}, callSpan);
      c->lanes = {uint8_t(i)};
      c = prim(Prim::FAbs, f, {c}, callSpan);
      largest = largest ? prim(Prim::FMax, f, {largest, c}, callSpan) : c;
    }
    // Inside the rare branch: m once, then m sqrt((v / m).(v / m)) when 0 < m < inf.
    std::vector<std::pair<int, Node*>> mLets, wLets;
    Node* m = bindOnce(largest, mLets);
    Node* wRef = bindOnce(prim(Prim::FDiv, v->type, {v, splatTo(m, v->type, callSpan)}, callSpan), wLets);
    Node* scaledLength = prim(Prim::FMul, f, {m, prim(Prim::FSqrt, f, {prim(Prim::Dot, f, {wRef, wRef}, callSpan)}, callSpan)}, callSpan);
    Node* usable = program.node(Node::Kind::And, types.boolean(), callSpan);
    usable->args = {prim(Prim::FGt, types.boolean(), {m, constFloat(0, callSpan)}, callSpan),
                    prim(Prim::FLt, types.boolean(), {m, constFloat(std::numeric_limits<float>::infinity(), callSpan)}, callSpan)};
    Node* plain = prim(Prim::FSqrt, f, {d}, callSpan);
    Node* scaled = program.node(Node::Kind::If, f, callSpan);
    scaled->args = {usable, wrapLets(wLets, scaledLength), prim(Prim::FSqrt, f, {d}, callSpan)};
    Node* n = program.node(Node::Kind::If, f, callSpan);
    n->args = {normal, plain, wrapLets(mLets, scaled)};
    return n;
  };
  if (name == "dot" || name == "distance") {
    if (!arity(2) || !isVectorLike(0) || args[0].node->type != args[1].node->type) return noOverload("two vectors of one type");
    Node* a = args[0].node;
    Node* b = args[1].node;
    if (name == "dot") return prim(Prim::Dot, types.floating(), {a, b}, callSpan);
    Node* d = bindOnce(prim(Prim::FSub, a->type, {a, b}, callSpan), lets);
    return wrapLets(lets, safeLength(d));
  }
  if (name == "length" || name == "normalize") {
    if (!arity(1) || !isVectorLike(0)) return noOverload("a vector");
    Node* v = bindOnce(args[0].node, lets);
    Node* len = safeLength(v);
    if (name == "length") return wrapLets(lets, len);
    len = bindOnce(len, lets);
    Node* positive = prim(Prim::FGt, types.boolean(), {len, constFloat(0, callSpan)}, callSpan);
    Node* n = program.node(Node::Kind::If, v->type, callSpan);
    n->args = {positive, prim(Prim::FDiv, v->type, {v, splatTo(len, v->type, callSpan)}, callSpan),
               splatTo(constFloat(0, callSpan), v->type, callSpan)};
    return wrapLets(lets, n);
  }
  if (name == "cross") {
    const Type* v3 = types.vec(3);
    if (!arity(2) || args[0].node->type != v3 || args[1].node->type != v3) return noOverload("two Vec3");
    Node* a = bindOnce(args[0].node, lets);
    Node* b = bindOnce(args[1].node, lets);
    auto sw = [&](Node* v, uint8_t i, uint8_t j, uint8_t k) {
      Node* s = prim(Prim::Swizzle, v3, {v}, callSpan);
      s->lanes = {i, j, k};
      return s;
    };
    // a.yzx * b.zxy - a.zxy * b.yzx
    Node* l = prim(Prim::FMul, v3, {sw(a, 1, 2, 0), sw(b, 2, 0, 1)}, callSpan);
    Node* r = prim(Prim::FMul, v3, {sw(a, 2, 0, 1), sw(b, 1, 2, 0)}, callSpan);
    return wrapLets(lets, prim(Prim::FSub, v3, {l, r}, callSpan));
  }
  if (name == "float") {
    if (!arity(1) || (kind(0) != TypeKind::Int && kind(0) != TypeKind::Float)) return noOverload("an Int or Float");
    return toFloat(args[0].node, callSpan);
  }
  if (name == "int") {
    if (!arity(1) || (kind(0) != TypeKind::Int && kind(0) != TypeKind::Float)) return noOverload("a Float or Int");
    if (kind(0) == TypeKind::Int) return args[0].node;
    return prim(Prim::FloatToInt, types.integer(), {args[0].node}, callSpan);
  }
  if (name == "is_nan" || name == "is_inf") {
    if (!arity(1) || (kind(0) != TypeKind::Int && kind(0) != TypeKind::Float)) return noOverload("a Float");
    return prim(name == "is_nan" ? Prim::FIsNan : Prim::FIsInf, types.boolean(), {toFloat(args[0].node, callSpan)}, callSpan);
  }
  if (name == "vec2" || name == "vec3" || name == "vec4" || name == "rgb") {
    int lanes = name == "rgb" ? 3 : name[3] - '0';
    const Type* target = name == "rgb" ? types.color() : types.vec(lanes);
    if (arity(1) && (kind(0) == TypeKind::Int || kind(0) == TypeKind::Float))
      return splatTo(args[0].node, target, callSpan);
    int total = 0;
    std::vector<Node*> parts;
    for (size_t i = 0; i < args.size(); ++i) {
      Node* part = toFloat(args[i].node, callSpan);
      int n = part->type->fixedLanes();
      if (n == 0 || (name == "rgb" && n != 1)) return noOverload(name == "rgb" ? "(r, g, b) or one Float" : "scalars and vectors whose sizes add up");
      total += n;
      parts.push_back(part);
    }
    if (total != lanes) return noOverload(name == "rgb" ? "(r, g, b) or one Float" : "scalars and vectors whose sizes add up");
    return prim(Prim::Concat, target, parts, callSpan);
  }
  if (name == "color") {
    if (!arity(1) || args[0].node->type != types.vec(3)) return noOverload("a Vec3");
    return prim(Prim::Concat, types.color(), {args[0].node}, callSpan);
  }
  if (name == "reflectance_spectrum" || name == "unbounded_spectrum" || name == "illuminant_spectrum") {
    if (!arity(1) || kind(0) != TypeKind::Color) return noOverload("a Color (linear sRGB)");
    const Prim p = name == "reflectance_spectrum" ? Prim::RgbReflectance
                   : name == "unbounded_spectrum" ? Prim::RgbUnbounded
                                                  : Prim::RgbIlluminant;
    return prim(p, types.spectrum(), {args[0].node}, callSpan);
  }
  if (name == "luminance") {
    if (!arity(1) || kind(0) != TypeKind::Color) return noOverload("a Color");
    static const float weights[3] = {0.2126f, 0.7152f, 0.0722f};
    return prim(Prim::Dot, types.floating(), {args[0].node, constLanes(types.color(), weights, callSpan)}, callSpan);
  }
  if (name == "spectrum") {
    if (!arity(1) || (kind(0) != TypeKind::Int && kind(0) != TypeKind::Float)) return noOverload("a Float");
    return splatTo(args[0].node, types.spectrum(), callSpan);
  }
  // Material operands: a Float (or Int) is a constant spectrum where a Color or Spectrum is
  // expected; null when the argument does not fit.
  auto scalar = [&](size_t i) -> Node* {
    return kind(i) == TypeKind::Int || kind(i) == TypeKind::Float ? toFloat(args[i].node, callSpan) : nullptr;
  };
  auto spectrumArg = [&](size_t i) -> Node* {
    if (kind(i) == TypeKind::Spectrum) return args[i].node;
    Node* x = scalar(i);
    return x ? splatTo(x, types.spectrum(), callSpan) : nullptr;
  };
  auto colorOrSpectrumArg = [&](size_t i) -> Node* {
    return kind(i) == TypeKind::Color ? args[i].node : spectrumArg(i);
  };
  auto materialArg = [&](size_t i) -> Node* { return kind(i) == TypeKind::Material ? args[i].node : nullptr; };
  auto material = [&](Prim p, std::vector<Node*> operands, const char* expected) -> Node* {
    for (Node* x : operands)
      if (!x) return noOverload(expected);
    return prim(p, types.material(), std::move(operands), callSpan);
  };
  // A roughness argument at `at` with its rotation at `rotationAt`, appended to `operands`: a
  // Float (isotropic: one scalar, the rotation dropped) or a Vec2 (alpha along u, alpha along v)
  // and the Float rotation of those axes in radians (three scalars: an anisotropic node). A
  // null operand when the types do not fit.
  auto roughnessArgs = [&](size_t at, size_t rotationAt, std::vector<Node*>& operands) {
    if (kind(at) != TypeKind::Vec2) {
      operands.push_back(scalar(rotationAt) ? scalar(at) : nullptr);
      return;
    }
    Node* r = bindOnce(args[at].node, lets);
    operands.push_back(swizzle(r, "x", args[at].span));
    operands.push_back(swizzle(r, "y", args[at].span));
    operands.push_back(scalar(rotationAt));
  };
  if (name == "diffuse" || name == "emission") {
    if (!arity(1)) return noOverload("a Color or Spectrum");
    return material(name == "diffuse" ? Prim::MatDiffuse : Prim::MatEmission, {colorOrSpectrumArg(0)}, "a Color or Spectrum");
  }
  if (name == "dielectric") {
    // The interior's IOR relative to the outside; a Float is a constant spectrum. The tint
    // filters the transmission at each crossing (glTF's coloured glass), never the reflection.
    const char* expected =
        "(ior, roughness = 0.0, transmission_tint = 1.0, rotation = 0.0): an IOR Float or Spectrum, a Float or Vec2, "
        "a Color, Spectrum or Float, and a Float";
    if (!arity(4)) return noOverload(expected);
    std::vector<Node*> operands = {spectrumArg(0), colorOrSpectrumArg(2)};
    roughnessArgs(1, 3, operands);
    Node* m = material(Prim::MatDielectric, operands, expected);
    return m->type->isError() ? m : wrapLets(lets, m);
  }
  if (name == "conductor") {
    // eta and k each a Color or Spectrum; a Float takes the other's type if that is a Color,
    // else it is a constant spectrum.
    const char* expected =
        "(eta, k, roughness = 0.0, rotation = 0.0), eta and k each a Color, Spectrum or Float, roughness a Float or "
        "Vec2, rotation a Float";
    if (!arity(4)) return noOverload(expected);
    std::vector<Node*> operands;
    for (size_t i = 0; i < 2; ++i) {
      Node* x = scalar(i);
      if (x && kind(1 - i) == TypeKind::Color) x = splatTo(x, types.color(), callSpan);
      operands.push_back(x && x->type->kind == TypeKind::Color ? x : colorOrSpectrumArg(i));
    }
    roughnessArgs(2, 3, operands);
    Node* m = material(Prim::MatConductor, operands, expected);
    return m->type->isError() ? m : wrapLets(lets, m);
  }
  if (name == "thin_dielectric") {
    // A rough wall (roughness > 0) scatters around both the mirror and the straight-through
    // direction (renderer/bsdf/thin_dielectric.cpp); the tint multiplies the transmission only.
    const char* expected =
        "(ior, roughness = 0.0, transmission_tint = 1.0): an IOR Float or Spectrum, a Float, and a Color, Spectrum or Float";
    if (!arity(3)) return noOverload(expected);
    return material(Prim::MatThinDielectric, {spectrumArg(0), colorOrSpectrumArg(2), scalar(1)}, expected);
  }
  if (name == "glossy") {
    const char* expected = "(reflectance: Color, Spectrum or Float, n: Float)";
    if (!arity(2)) return noOverload(expected);
    return material(Prim::MatGlossy, {colorOrSpectrumArg(0), scalar(1)}, expected);
  }
  if (name == "glossy_dielectric") {
    const char* expected = "(ior: Float or Spectrum, n: Float)";
    if (!arity(2)) return noOverload(expected);
    return material(Prim::MatGlossyDielectric, {spectrumArg(0), scalar(1)}, expected);
  }
  if (name == "sheen") {
    // Cloth sheen (Charlie, Estevez & Kulla 2017): a colour and its roughness alpha.
    const char* expected = "(color: Color, Spectrum or Float, roughness: Float)";
    if (!arity(2)) return noOverload(expected);
    return material(Prim::MatSheen, {colorOrSpectrumArg(0), scalar(1)}, expected);
  }
  if (name == "layer" || name == "add_material") {
    const char* expected = name == "layer" ? "(coat: Material, base: Material)" : "(a: Material, b: Material)";
    if (!arity(2)) return noOverload(expected);
    return material(name == "layer" ? Prim::MatLayer : Prim::MatAdd, {materialArg(0), materialArg(1)}, expected);
  }
  if (name == "scale_material") {
    const char* expected = "(m: Material, w: Color, Spectrum or Float)";
    if (!arity(2)) return noOverload(expected);
    return material(Prim::MatScale, {materialArg(0), colorOrSpectrumArg(1)}, expected);
  }
  if (name == "mix_material") {
    const char* expected = "(Material, Material, Float)";
    if (!arity(3)) return noOverload(expected);
    return material(Prim::MatMix, {materialArg(0), materialArg(1), scalar(2)}, expected);
  }
  if (Node* n = imageBuiltin(name, args, calleeSpan, callSpan)) return n;
  if (name == "fold") {
    if (!arity(3) || kind(0) != TypeKind::Int) return noOverload("(n: Int, init, f: (acc, Int) -> acc)");
    Node* f = args[2].node;
    if (!f->type->isCallable() || f->type->kind == TypeKind::BuiltinRef)
      return noOverload("(n: Int, init, f) where f is a lambda or a named function");
    Node* init = args[1].node;
    int idx = foldStep(f, init->type, args[2].span);
    if (idx < 0) return errorNode(callSpan);
    const Type* result = program.functions[idx].resultType;
    if (result->isError()) return errorNode(callSpan);
    if (result != init->type) {
      // An Int accumulator whose step gives Float becomes a Float accumulator.
      if (init->type->kind == TypeKind::Int && result->kind == TypeKind::Float) {
        init = toFloat(init, args[1].span);
        idx = foldStep(f, init->type, args[2].span);
        if (idx < 0) return errorNode(callSpan);
        result = program.functions[idx].resultType;
      }
      if (result != init->type) {
        if (!result->isError())
          error("E0401", args[2].span, "fold's step returns " + typeName(result) + " but the accumulator is " + typeName(init->type));
        return errorNode(callSpan);
      }
    }
    Node* n = program.node(Node::Kind::Fold, init->type, callSpan);
    n->callee = idx;
    n->args = {args[0].node, init};
    if (f->type->kind == TypeKind::Lambda) n->args.push_back(f);
    return n;
  }
  return noOverload("a known builtin");
}

// fold calls its step as an ordinary call f(acc, i) (docs/language.md 4.3): arity, named
// parameters' defaults and annotations apply as at any call site. The step is a function of
// (the closure for a lambda, acc, i) whose body is that call. fold had instantiated f with the
// argument types directly, so a step's default was never bound, a step of the wrong arity gave
// no diagnostic, and annotations were ignored (fn step(acc: Float, i: Float) folded Ints).
int Builder::foldStep(Node* f, const Type* acc, Span at) {
  Builder body(impl, module);
  std::vector<const Type*> paramTypes;
  Node* callee = f;  // a named function is called by its declaration, never evaluated
  if (f->type->kind == TypeKind::Lambda) {
    callee = body.local(body.declareLocal("", f->type), f->type, at);
    paramTypes.push_back(f->type);
  }
  const int accSlot = body.declareLocal("", acc);
  const int indexSlot = body.declareLocal("", types.integer());
  paramTypes.push_back(acc);
  paramTypes.push_back(types.integer());
  std::vector<TypedArg> callArgs(2);
  callArgs[0].span = callArgs[1].span = at;
  callArgs[0].node = body.local(accSlot, acc, at);
  callArgs[1].node = body.local(indexSlot, types.integer(), at);
  Node* result = body.apply(callee, at, std::move(callArgs), at, nullptr);
  hadError_ |= body.hadError();
  if (result->type->isError()) return -1;
  ir::Function fn;
  fn.name = "<fold step>";
  fn.span = at;
  fn.paramTypes = std::move(paramTypes);
  fn.resultType = result->type;
  fn.body = result;
  fn.numSlots = body.numSlots();
  program.functions.push_back(std::move(fn));
  return int(program.functions.size()) - 1;
}

}  // namespace tex::lang
