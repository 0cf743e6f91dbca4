// Runtime values of the reference interpreter, and their canonical printing
// (docs/language.md section 8).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lang/types.h"

namespace tex::lang {

constexpr int kMaxLanes = 8;  // the largest wavelength group

struct MaterialNode;

struct Value {
  float f[kMaxLanes] = {};  // float lanes of Float, Vec2-4, Color, Spectrum
  int32_t i = 0;            // Int; Bool is i != 0
  std::shared_ptr<const std::vector<Value>> fields;    // records and lambda captures
  std::shared_ptr<const MaterialNode> material;        // Material

  static Value ofFloat(float x) { Value v; v.f[0] = x; return v; }
  static Value ofInt(int32_t x) { Value v; v.i = x; return v; }
  static Value ofBool(bool x) { Value v; v.i = x ? 1 : 0; return v; }
};

// A closure tree: the renderer issues grow the set of lobes. Kinds carry the ABI's
// ClosureKind numbers (compiler/abi.h static_asserts it), and fields are used as there.
struct MaterialNode {
  enum class Kind : uint32_t {
    Diffuse = 1, Emission = 2, Mix = 3, Dielectric = 4, Conductor = 5, ThinDielectric = 6,
    Glossy = 7, GlossyDielectric = 8, Layer = 9, Scale = 10, Add = 11, Sheen = 12,
  } kind = Kind::Diffuse;
  const Type* paramType = nullptr;   // Color or Spectrum, for kinds with parameters
  Value param;                       // albedo, radiance, IOR, eta, reflectance or Scale's weight
  const Type* param2Type = nullptr;  // Conductor: Color or Spectrum
  Value param2;                      // Conductor: k (extinction)
  uint32_t flags = 0;                // kMaterialVariesWithWavelength (decided statically)
  std::shared_ptr<const MaterialNode> a, b;  // Mix, Layer (coat, base), Add; Scale: a
  float weight = 0;                          // Mix: weight of b
  float scalars[4] = {};                     // roughness (Dielectric, Conductor; kMaterialAnisotropic: 3), n (Glossy*)
};

// MaterialNode::flags bit 0: the node's parameters depend on the wavelength (lambda_nm); the
// same bit as compiler::kClosureVariesWithWavelength (docs/abi.md, "Materials").
constexpr uint32_t kMaterialVariesWithWavelength = 1;
// Bit 1: an anisotropic roughness, scalars[0..2] = alpha along u, alpha along v, the rotation
// of those axes (Dielectric, Conductor); compiler::kClosureAnisotropic.
constexpr uint32_t kMaterialAnisotropic = 2;

// The wavelengths at which Spectrum values are evaluated.
struct WavelengthGroup {
  int count = 4;
  float lambdaNm[kMaxLanes] = {400, 500, 600, 700};
};

int lanesOf(const Type* t, const WavelengthGroup& group);
std::string formatFloat(float x);
std::string formatValue(const Value& v, const Type* t, const WavelengthGroup& group);

}  // namespace tex::lang
