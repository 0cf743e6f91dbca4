// The typed core IR: monomorphic, first-order, no lambdas left (they are lifted into
// functions taking their captures as a record), no overloading (every operation is a
// primitive on exact operand types), no implicit conversions. The interpreter evaluates it;
// the compiler lowers it to LLVM.
#pragma once
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <functional>
#include <string>
#include <vector>

#include "lang/source.h"
#include "lang/types.h"

namespace tex::lang::ir {

// Primitive operations. "Lane-wise" ops apply per float lane of a float-based type
// (Float, Vec2-4, Color, Spectrum); all operands have the result's type unless noted.
enum class Prim : uint8_t {
  // lane-wise float arithmetic
  FAdd, FSub, FMul, FDiv, FRem, FNeg, FMin, FMax, FAbs, FSign, FFloor, FCeil, FTrunc, FRound,
  FSqrt, FExp, FExp2, FLog, FLog2, FSin, FCos, FTan, FAsin, FAcos, FAtan, FSinh, FCosh, FTanh,
  FPow, FAtan2,
  FStep,  // lane-wise: x < edge ? 0 : 1 (args: edge, x)
  // float comparisons: Float operands, Bool result; FEq/FNe compare all lanes of any float type
  FLt, FLe, FGt, FGe, FEq, FNe,
  FIsNan, FIsInf,  // Float -> Bool
  // Int
  IAdd, ISub, IMul, IDiv, IRem, INeg, IAnd, IOr, IXor, IShl, IShr, INot, IMin, IMax, IAbs,
  ILt, ILe, IGt, IGe, IEq, INe,
  // Bool
  BNot, BEq, BNe,
  // conversions and shapes
  IntToFloat,   // Int -> Float
  FloatToInt,   // Float -> Int (truncate, NaN -> 0, saturate)
  Splat,        // Float -> any float-based type (every lane)
  Concat,       // float-based operands -> float-based result, lanes concatenated
  Swizzle,      // float-based -> float-based; `lanes` holds the source lane indices
  Dot,          // two equal float-based -> Float
  Wavelengths,  // () -> Spectrum: the context's wavelengths in nm
  // materials (operands in the order of MaterialShape: children, parameter vectors, scalars, weight)
  MatDiffuse,   // Color|Spectrum -> Material
  MatEmission,  // Color|Spectrum -> Material
  MatMix,       // (Material, Material, Float) -> Material
  MatDielectric,  // (ior: Spectrum (interior over exterior), tint, roughness: Float[, roughness_v, rotation]) -> Material
  MatConductor,   // (eta: Color|Spectrum, k: Color|Spectrum, roughness: Float[, roughness_v, rotation]) -> Material
  MatThinDielectric,    // ior: Spectrum, roughness: Float -> Material
  MatGlossy,            // (reflectance: Color|Spectrum, n: Float) -> Material
  MatGlossyDielectric,  // (ior: Spectrum, n: Float) -> Material
  MatLayer,             // (coat: Material, base: Material) -> Material
  MatScale,             // (m: Material, w: Color|Spectrum) -> Material
  MatAdd,               // (Material, Material) -> Material
  MatSheen,             // (color: Color|Spectrum, roughness: Float) -> Material
  // image textures (lang/image_table.h): (Image, uv: Vec2, duvdx: Vec2, duvdy: Vec2, wrap: Int)
  // -> Vec4 RGBA; the nearest and bilinear lookups ignore the derivatives
  ImageNearest, ImageBilinear, ImageTrilinear,
  ImageSize,  // Image -> Vec2 (width, height in texels)
  // RGB to spectrum (lang/rgb_upsampling.h): Color -> Spectrum at the context's wavelengths
  RgbReflectance, RgbUnbounded, RgbIlluminant,
};

// How a material primitive's operands fill a closure node (docs/abi.md, "Materials"): first
// `children` Materials (node fields a, b), then `params` Color/Spectrum vectors (params,
// params2), then `scalars` Floats (scalars[0..]), then the Mix weight if `weight`. `kind` is
// the ABI's ClosureKind number; the interpreter's MaterialNode::Kind uses the same numbers.
struct MaterialShape {
  uint32_t kind = 0;
  int children = 0, params = 0, scalars = 0;
  bool weight = false;
  // Dielectric and Conductor: 3, the scalars of an anisotropic roughness (alpha_u, alpha_v,
  // rotation), which a primitive with that many scalar operands has; its node gets the
  // anisotropic flag (docs/abi.md). 0 for the other kinds.
  int anisotropicScalars = 0;
};
// The number of scalar operands of material primitive `n` (shape.scalars, or
// shape.anisotropicScalars for an anisotropic roughness).
int materialScalarCount(const struct Node* n, const MaterialShape& shape);
// Null for a primitive that builds no material.
const MaterialShape* materialShape(Prim p);
const MaterialShape* materialShapeOfKind(uint32_t kind);
// The builtin that builds closure kind `kind` ("diffuse", "layer", ...), or null.
const char* materialBuiltinName(uint32_t kind);

// True for the material primitives whose closure nodes carry parameter vectors, and therefore
// the wavelength-dependence flag.
inline bool isMaterialLeaf(Prim p) {
  const MaterialShape* shape = materialShape(p);
  return shape && shape->params > 0;
}
const char* primName(Prim p);

struct Node {
  enum class Kind : uint8_t {
    Const,      // constant: type + value fields (an Image constant's intValue is its handle)
    Local,      // slot
    Let,        // slot = args[0]; value of args[1]
    If,         // args[0] ? args[1] : args[2]
    And, Or,    // short-circuit Bool
    Prim,       // prim(args...)
    Call,       // functions[callee](args...)
    MakeRecord, // fields in the record type's (sorted) order; also builds lambda captures
    GetField,   // args[0].fields[index]
    Fold,       // acc = args[1]; for i in [0, args[0]): acc = functions[callee](args[2], acc, i)
  } kind;
  const Type* type = nullptr;
  Prim prim = Prim::FAdd;
  int slot = -1;
  int callee = -1;
  int index = -1;
  std::vector<uint8_t> lanes;  // Swizzle source lanes
  // Const payload
  float floatValue[8] = {};
  int32_t intValue = 0;
  bool boolValue = false;
  std::vector<Node*> args;
  Span span;
};

struct Function {
  std::string name;  // for messages and dumps, e.g. "noise.fbm<Int, <lambda>, Vec3>"
  std::vector<const Type*> paramTypes;
  const Type* resultType = nullptr;
  Node* body = nullptr;
  int numSlots = 0;  // params occupy slots [0, paramTypes.size())
  Span span;
};

// A whole program: functions reference each other by index.
struct Program {
  std::deque<Node> nodes;
  std::vector<Function> functions;

  Node* node(Node::Kind kind, const Type* type, Span span) {
    Node& n = nodes.emplace_back();
    n.kind = kind;
    n.type = type;
    n.span = span;
    return &n;
  }
};

std::string dump(const Program& program, int function);

// How deep evaluating `function` nests once every call and fold is expanded in place: the
// depth of its body's tree, a call adding its callee's inlined depth under it. The interpreter
// and the compiler recurse that deep; Session refuses entries beyond kMaxInlinedDepth (E0413).
// Iterative (no recursion of its own), memoised per function in `memo`.
constexpr uint64_t kMaxInlinedDepth = 65536;
uint64_t inlinedDepth(const Program& program, int function, std::map<int, uint64_t>& memo);

// A value per function computed from its body and its callees' values (inlined size, inlined
// depth), bottom-up over the call graph without recursion, memoised in `memo`.
// summarise(g, callee) computes g's value given callee(c), which returns c's value or nullopt
// when c is not known yet (summarise then returns nullopt too, after asking for every callee
// it needs). A callee that is an ancestor of g (a cycle: no valid program has one) is 0.
uint64_t bottomUpOverCalls(
    int function, std::map<int, uint64_t>& memo,
    const std::function<std::optional<uint64_t>(int, const std::function<std::optional<uint64_t>(int)>&)>& summarise);

}  // namespace tex::lang::ir
