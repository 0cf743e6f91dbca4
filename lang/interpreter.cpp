#include "lang/interpreter.h"

#include "lang/rgb_upsampling.h"

#include <bit>
#include <cmath>
#include <limits>
#include <memory>

#include "lang/image_table.h"
#include "lang/wavelength_dependence.h"

namespace tex::lang {

using ir::Node;
using ir::Prim;

namespace {

int32_t wrapAdd(int32_t a, int32_t b) { return int32_t(uint32_t(a) + uint32_t(b)); }
int32_t wrapSub(int32_t a, int32_t b) { return int32_t(uint32_t(a) - uint32_t(b)); }
int32_t wrapMul(int32_t a, int32_t b) { return int32_t(uint32_t(a) * uint32_t(b)); }

int32_t intDiv(int32_t a, int32_t b) {
  if (b == 0) return 0;
  if (a == std::numeric_limits<int32_t>::min() && b == -1) return a;
  return a / b;
}
int32_t intRem(int32_t a, int32_t b) {
  if (b == 0 || b == -1) return 0;
  return a % b;
}

int32_t floatToInt(float x) {
  if (std::isnan(x)) return 0;
  if (x >= 2147483648.0f) return std::numeric_limits<int32_t>::max();
  if (x <= -2147483648.0f) return std::numeric_limits<int32_t>::min();
  return int32_t(x);
}

float fsign(float x) { return x > 0 ? 1.0f : x < 0 ? -1.0f : x; }

class Interpreter {
 public:
  Interpreter(const ir::Program& p, const WavelengthGroup& g, int entry, ClosureBudget& budget)
      : program_(p), group_(g), entry_(entry), budget_(budget) {}

  Value call(int function, std::vector<Value> args) {
    const ir::Function& fn = program_.functions[size_t(function)];
    args.resize(size_t(std::max<int>(fn.numSlots, int(args.size()))));
    return eval(fn.body, args);
  }

 private:
  int lanes(const Type* t) const { return lanesOf(t, group_); }

  Value eval(const Node* n, std::vector<Value>& slots) {
    switch (n->kind) {
      case Node::Kind::Const: {
        Value v;
        for (int i = 0; i < kMaxLanes; ++i) v.f[i] = n->floatValue[i];
        v.i = n->type->kind == TypeKind::Bool ? (n->boolValue ? 1 : 0) : n->intValue;
        return v;
      }
      case Node::Kind::Local: return slots[size_t(n->slot)];
      case Node::Kind::Let:
        slots[size_t(n->slot)] = eval(n->args[0], slots);
        return eval(n->args[1], slots);
      case Node::Kind::If: return eval(n->args[0], slots).i ? eval(n->args[1], slots) : eval(n->args[2], slots);
      case Node::Kind::And: return Value::ofBool(eval(n->args[0], slots).i && eval(n->args[1], slots).i);
      case Node::Kind::Or: return Value::ofBool(eval(n->args[0], slots).i || eval(n->args[1], slots).i);
      case Node::Kind::Prim: return evalPrim(n, slots);
      case Node::Kind::Call: {
        std::vector<Value> args;
        args.reserve(n->args.size());
        for (const Node* a : n->args) args.push_back(eval(a, slots));
        stack_.push_back(n);
        Value result = call(n->callee, std::move(args));
        stack_.pop_back();
        return result;
      }
      case Node::Kind::MakeRecord: {
        auto fields = std::make_shared<std::vector<Value>>();
        fields->reserve(n->args.size());
        for (const Node* a : n->args) fields->push_back(eval(a, slots));
        Value v;
        v.fields = std::move(fields);
        return v;
      }
      case Node::Kind::GetField: {
        Value base = eval(n->args[0], slots);
        return (*base.fields)[size_t(n->index)];
      }
      case Node::Kind::Fold: {
        int32_t count = eval(n->args[0], slots).i;
        Value acc = eval(n->args[1], slots);
        bool hasClosure = n->args.size() > 2;
        Value closure = hasClosure ? eval(n->args[2], slots) : Value{};
        stack_.push_back(n);
        for (int32_t i = 0; i < count; ++i) {
          std::vector<Value> args;
          if (hasClosure) args.push_back(closure);
          args.push_back(std::move(acc));
          args.push_back(Value::ofInt(i));
          acc = call(n->callee, std::move(args));
        }
        stack_.pop_back();
        return acc;
      }
    }
    return {};
  }

  template <typename F>
  Value mapLanes(const Node* n, std::vector<Value>& slots, F f) {
    Value x = eval(n->args[0], slots);
    Value r;
    int k = lanes(n->type);
    for (int i = 0; i < k; ++i) r.f[i] = f(x.f[i]);
    return r;
  }
  template <typename F>
  Value zipLanes(const Node* n, std::vector<Value>& slots, F f) {
    Value x = eval(n->args[0], slots);
    Value y = eval(n->args[1], slots);
    Value r;
    int k = lanes(n->type);
    for (int i = 0; i < k; ++i) r.f[i] = f(x.f[i], y.f[i]);
    return r;
  }
  template <typename F>
  Value ints(const Node* n, std::vector<Value>& slots, F f) {
    int32_t x = eval(n->args[0], slots).i;
    int32_t y = n->args.size() > 1 ? eval(n->args[1], slots).i : 0;
    return Value::ofInt(f(x, y));
  }
  template <typename F>
  Value compareFloats(const Node* n, std::vector<Value>& slots, F f) {
    Value x = eval(n->args[0], slots);
    Value y = eval(n->args[1], slots);
    return Value::ofBool(f(x.f[0], y.f[0]));
  }

  // IEEE 754-2019 minimumNumber / maximumNumber (docs/language.md section 5): fminf / fmaxf,
  // which may return either zero when the operands compare equal, with -0 < +0. For equal
  // operands OR-ing (min) or AND-ing (max) their bits picks the signed zero and leaves equal
  // non-zero values as they are; the JIT does the same (compiler/codegen.cpp).
  static float minimumNumber(float a, float b) {
    if (a == b) return std::bit_cast<float>(std::bit_cast<uint32_t>(a) | std::bit_cast<uint32_t>(b));
    return std::fmin(a, b);
  }
  static float maximumNumber(float a, float b) {
    if (a == b) return std::bit_cast<float>(std::bit_cast<uint32_t>(a) & std::bit_cast<uint32_t>(b));
    return std::fmax(a, b);
  }

  Value evalPrim(const Node* n, std::vector<Value>& slots) {
    switch (n->prim) {
      case Prim::FAdd: return zipLanes(n, slots, [](float a, float b) { return a + b; });
      case Prim::FSub: return zipLanes(n, slots, [](float a, float b) { return a - b; });
      case Prim::FMul: return zipLanes(n, slots, [](float a, float b) { return a * b; });
      case Prim::FDiv: return zipLanes(n, slots, [](float a, float b) { return a / b; });
      case Prim::FRem: return zipLanes(n, slots, [](float a, float b) { return std::fmod(a, b); });
      case Prim::FMin: return zipLanes(n, slots, [](float a, float b) { return minimumNumber(a, b); });
      case Prim::FMax: return zipLanes(n, slots, [](float a, float b) { return maximumNumber(a, b); });
      case Prim::FPow: return zipLanes(n, slots, [](float a, float b) { return std::pow(a, b); });
      case Prim::FAtan2: return zipLanes(n, slots, [](float a, float b) { return std::atan2(a, b); });
      case Prim::FStep: return zipLanes(n, slots, [](float edge, float x) { return x < edge ? 0.0f : 1.0f; });
      case Prim::FNeg: return mapLanes(n, slots, [](float a) { return -a; });
      case Prim::FAbs: return mapLanes(n, slots, [](float a) { return std::fabs(a); });
      case Prim::FSign: return mapLanes(n, slots, fsign);
      case Prim::FFloor: return mapLanes(n, slots, [](float a) { return std::floor(a); });
      case Prim::FCeil: return mapLanes(n, slots, [](float a) { return std::ceil(a); });
      case Prim::FTrunc: return mapLanes(n, slots, [](float a) { return std::trunc(a); });
      case Prim::FRound: return mapLanes(n, slots, [](float a) { return std::round(a); });
      case Prim::FSqrt: return mapLanes(n, slots, [](float a) { return std::sqrt(a); });
      case Prim::FExp: return mapLanes(n, slots, [](float a) { return std::exp(a); });
      case Prim::FExp2: return mapLanes(n, slots, [](float a) { return std::exp2(a); });
      case Prim::FLog: return mapLanes(n, slots, [](float a) { return std::log(a); });
      case Prim::FLog2: return mapLanes(n, slots, [](float a) { return std::log2(a); });
      case Prim::FSin: return mapLanes(n, slots, [](float a) { return std::sin(a); });
      case Prim::FCos: return mapLanes(n, slots, [](float a) { return std::cos(a); });
      case Prim::FTan: return mapLanes(n, slots, [](float a) { return std::tan(a); });
      case Prim::FAsin: return mapLanes(n, slots, [](float a) { return std::asin(a); });
      case Prim::FAcos: return mapLanes(n, slots, [](float a) { return std::acos(a); });
      case Prim::FAtan: return mapLanes(n, slots, [](float a) { return std::atan(a); });
      case Prim::FSinh: return mapLanes(n, slots, [](float a) { return std::sinh(a); });
      case Prim::FCosh: return mapLanes(n, slots, [](float a) { return std::cosh(a); });
      case Prim::FTanh: return mapLanes(n, slots, [](float a) { return std::tanh(a); });
      case Prim::FLt: return compareFloats(n, slots, [](float a, float b) { return a < b; });
      case Prim::FLe: return compareFloats(n, slots, [](float a, float b) { return a <= b; });
      case Prim::FGt: return compareFloats(n, slots, [](float a, float b) { return a > b; });
      case Prim::FGe: return compareFloats(n, slots, [](float a, float b) { return a >= b; });
      case Prim::FEq:
      case Prim::FNe: {
        Value x = eval(n->args[0], slots);
        Value y = eval(n->args[1], slots);
        bool equal = true;
        int k = lanes(n->args[0]->type);
        for (int i = 0; i < k; ++i) equal = equal && x.f[i] == y.f[i];
        return Value::ofBool(n->prim == Prim::FEq ? equal : !equal);
      }
      case Prim::FIsNan: return Value::ofBool(std::isnan(eval(n->args[0], slots).f[0]));
      case Prim::FIsInf: return Value::ofBool(std::isinf(eval(n->args[0], slots).f[0]));
      case Prim::IAdd: return ints(n, slots, wrapAdd);
      case Prim::ISub: return ints(n, slots, wrapSub);
      case Prim::IMul: return ints(n, slots, wrapMul);
      case Prim::IDiv: return ints(n, slots, intDiv);
      case Prim::IRem: return ints(n, slots, intRem);
      case Prim::INeg: return ints(n, slots, [](int32_t a, int32_t) { return wrapSub(0, a); });
      case Prim::IAnd: return ints(n, slots, [](int32_t a, int32_t b) { return a & b; });
      case Prim::IOr: return ints(n, slots, [](int32_t a, int32_t b) { return a | b; });
      case Prim::IXor: return ints(n, slots, [](int32_t a, int32_t b) { return a ^ b; });
      case Prim::IShl: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(uint32_t(a) << (b & 31)); });
      case Prim::IShr: return ints(n, slots, [](int32_t a, int32_t b) { return a >> (b & 31); });
      case Prim::INot: return ints(n, slots, [](int32_t a, int32_t) { return ~a; });
      case Prim::IMin: return ints(n, slots, [](int32_t a, int32_t b) { return a < b ? a : b; });
      case Prim::IMax: return ints(n, slots, [](int32_t a, int32_t b) { return a > b ? a : b; });
      case Prim::IAbs: return ints(n, slots, [](int32_t a, int32_t) { return a < 0 ? wrapSub(0, a) : a; });
      case Prim::ILt: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a < b); });
      case Prim::ILe: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a <= b); });
      case Prim::IGt: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a > b); });
      case Prim::IGe: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a >= b); });
      case Prim::IEq: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a == b); });
      case Prim::INe: return ints(n, slots, [](int32_t a, int32_t b) { return int32_t(a != b); });
      case Prim::BNot: return Value::ofBool(!eval(n->args[0], slots).i);
      case Prim::BEq: return Value::ofBool(eval(n->args[0], slots).i == eval(n->args[1], slots).i);
      case Prim::BNe: return Value::ofBool(eval(n->args[0], slots).i != eval(n->args[1], slots).i);
      case Prim::IntToFloat: return Value::ofFloat(float(eval(n->args[0], slots).i));
      case Prim::FloatToInt: return Value::ofInt(floatToInt(eval(n->args[0], slots).f[0]));
      case Prim::Splat: {
        float x = eval(n->args[0], slots).f[0];
        Value r;
        for (int i = 0; i < lanes(n->type); ++i) r.f[i] = x;
        return r;
      }
      case Prim::Concat: {
        Value r;
        int at = 0;
        for (const Node* a : n->args) {
          Value x = eval(a, slots);
          int k = lanes(a->type);
          for (int i = 0; i < k && at < kMaxLanes; ++i) r.f[at++] = x.f[i];
        }
        return r;
      }
      case Prim::Swizzle: {
        Value x = eval(n->args[0], slots);
        Value r;
        for (size_t i = 0; i < n->lanes.size(); ++i) r.f[i] = x.f[n->lanes[i]];
        return r;
      }
      case Prim::Dot: {
        Value x = eval(n->args[0], slots);
        Value y = eval(n->args[1], slots);
        float sum = 0;
        int k = lanes(n->args[0]->type);
        for (int i = 0; i < k; ++i) sum = (i == 0) ? x.f[0] * y.f[0] : sum + x.f[i] * y.f[i];
        return Value::ofFloat(sum);
      }
      case Prim::Wavelengths: {
        Value r;
        for (int i = 0; i < group_.count; ++i) r.f[i] = group_.lambdaNm[i];
        return r;
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
      case Prim::MatSheen: return material(n, slots);
      case Prim::ImageNearest:
      case Prim::ImageBilinear:
      case Prim::ImageTrilinear: {
        // The same C++ lookup the JIT calls (compiler/runtime_functions.cpp).
        int32_t image = eval(n->args[0], slots).i;
        Value uv = eval(n->args[1], slots), dx = eval(n->args[2], slots), dy = eval(n->args[3], slots);
        int32_t wrap = eval(n->args[4], slots).i;
        ImageFilter filter = n->prim == Prim::ImageNearest    ? ImageFilter::Nearest
                             : n->prim == Prim::ImageBilinear ? ImageFilter::Bilinear
                                                              : ImageFilter::Trilinear;
        Value r;
        imageLookup(image, filter, wrap, uv.f[0], uv.f[1], dx.f[0], dx.f[1], dy.f[0], dy.f[1], r.f);
        return r;
      }
      case Prim::ImageSize: {
        Value r;
        imageSize(eval(n->args[0], slots).i, r.f);
        return r;
      }
      case Prim::RgbReflectance:
      case Prim::RgbUnbounded:
      case Prim::RgbIlluminant: {
        const Value c = eval(n->args[0], slots);
        const RgbUse use = n->prim == Prim::RgbReflectance ? RgbUse::Reflectance
                           : n->prim == Prim::RgbUnbounded ? RgbUse::Unbounded
                                                           : RgbUse::Illuminant;
        Value r;
        rgbToSpectrum(use, c.f, group_.lambdaNm, group_.count, r.f);
        return r;
      }
    }
    return {};
  }

  // A material node, its operands read in the order of ir::MaterialShape.
  Value material(const Node* n, std::vector<Value>& slots) {
    const ir::MaterialShape& shape = *ir::materialShape(n->prim);
    if (materialNodes_ >= budget_.nodeLimit) {  // a full arena: no tree, as compiled code gives -1
      budget_.overflowed = true;
      return {};
    }
    ++materialNodes_;
    auto m = std::make_shared<MaterialNode>();
    m->kind = MaterialNode::Kind(shape.kind);
    size_t at = 0;
    if (shape.children > 0) m->a = eval(n->args[at++], slots).material;
    if (shape.children > 1) m->b = eval(n->args[at++], slots).material;
    if (shape.params > 0) {
      m->paramType = n->args[at]->type;
      m->param = eval(n->args[at++], slots);
    }
    if (shape.params > 1) {
      m->param2Type = n->args[at]->type;
      m->param2 = eval(n->args[at++], slots);
    }
    const int scalars = ir::materialScalarCount(n, shape);
    for (int i = 0; i < scalars; ++i) m->scalars[i] = eval(n->args[at++], slots).f[0];
    if (shape.weight) m->weight = eval(n->args[at++], slots).f[0];
    if (shape.params > 0) m->flags = leafFlags(n);
    if (scalars != shape.scalars) m->flags |= kMaterialAnisotropic;
    Value v;
    v.material = std::move(m);
    return v;
  }

  // The leaf's flags in the context of the current call path (analysed on first use, so
  // programs that build no material pay nothing).
  uint32_t leafFlags(const Node* n) {
    if (!dependence_) dependence_ = std::make_unique<ir::WavelengthDependence>(program_);
    // An unknown context (there should be none) answers "varies", as in compiled code.
    int context = dependence_->entryContext(entry_);
    for (const Node* call : stack_) context = dependence_->calleeContext(context, call);
    return dependence_->flags(context, n);
  }

  const ir::Program& program_;
  const WavelengthGroup& group_;
  int entry_;
  std::vector<const Node*> stack_;  // the Call and Fold nodes from the entry to here
  ClosureBudget& budget_;
  size_t materialNodes_ = 0;
  std::unique_ptr<ir::WavelengthDependence> dependence_;
};

}  // namespace

Value evaluate(const ir::Program& program, int function, const std::vector<Value>& args, const WavelengthGroup& group,
               ClosureBudget* budget) {
  ClosureBudget local;
  return Interpreter(program, group, function, budget ? *budget : local).call(function, args);
}

static Value floats(std::initializer_list<float> xs) {
  Value v;
  int i = 0;
  for (float x : xs) v.f[i++] = x;
  return v;
}

Value makeHit(const float p[3], const float n[3], const float uv[2], float du, float dv) {
  // Fields in sorted order: dpdx, dpdy, duvdx, duvdy, n, p, uv.
  auto fields = std::make_shared<std::vector<Value>>();
  fields->push_back(floats({du, 0, 0}));
  fields->push_back(floats({0, dv, 0}));
  fields->push_back(floats({du, 0}));
  fields->push_back(floats({0, dv}));
  fields->push_back(floats({n[0], n[1], n[2]}));
  fields->push_back(floats({p[0], p[1], p[2]}));
  fields->push_back(floats({uv[0], uv[1]}));
  Value v;
  v.fields = std::move(fields);
  return v;
}

Value makeHit(float u, float v, float du, float dv) {
  const float p[3] = {u, v, 0};
  const float n[3] = {0, 0, 1};
  const float uv[2] = {u, v};
  return makeHit(p, n, uv, du, dv);
}

}  // namespace tex::lang
