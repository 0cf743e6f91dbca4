// The C ABI between compiled .tex code and its callers (docs/abi.md). Plain C layout: the
// renderer includes this header and nothing of LLVM.
#pragma once
#include <cstddef>
#include <cstdint>

namespace tex::compiler {

constexpr int kMaxWavelengths = 8;

// One closure node of a Material value (docs/abi.md, "Materials"). Kinds grow with the
// renderer's lobe set; unknown kinds are never produced by an older compiler.
enum class ClosureKind : uint32_t {
  Diffuse = 1,
  Emission = 2,
  Mix = 3,
  Dielectric = 4,        // params: IOR; scalars[0]: GGX roughness alpha (0 = smooth); [1], [2]: kClosureAnisotropic
  Conductor = 5,         // params: eta, params2: k; scalars[0]: GGX roughness alpha; [1], [2]: kClosureAnisotropic
  ThinDielectric = 6,    // params: IOR of a thin slab (no refraction offset); params2: transmission tint; scalars[0]: GGX alpha
  Glossy = 7,            // params: reflectance; scalars[0]: exponent n of the glossy model
  GlossyDielectric = 8,  // params: IOR; scalars[0]: exponent n
  Layer = 9,             // a: coat, b: base
  Scale = 10,            // a: child, params: weight
  Add = 11,              // a + b
  Sheen = 12,            // params: colour; scalars[0]: roughness alpha of the Charlie sheen
};
enum class ClosureParam : uint32_t { None = 0, Color = 1, Spectrum = 2 };

// ClosureNode::flags bit 0: the node's parameters depend on the wavelength (decided statically
// from the program, docs/abi.md): e.g. a dispersive IOR, for which the renderer keeps only
// the hero wavelength of a path after refraction.
constexpr uint32_t kClosureVariesWithWavelength = 1u << 0;
// ClosureNode::flags bit 1 (Dielectric, Conductor): anisotropic roughness; scalars[0] is the GGX
// alpha along the surface's u direction turned by scalars[2] radians toward v, scalars[1] the
// alpha across it. Without the bit scalars[1..2] are 0 and the roughness is isotropic.
constexpr uint32_t kClosureAnisotropic = 1u << 1;

struct ClosureNode {
  ClosureKind kind;
  ClosureParam paramKind;  // how `params` is to be read
  int32_t a, b;            // Mix, Layer, Add: child node indices; Scale: a; -1 when unused
  float weight;            // Mix: weight of b
  float params[kMaxWavelengths];   // Color: 3 floats; Spectrum: one per wavelength
  // Appended fields (older kinds leave them zero):
  float params2[kMaxWavelengths];  // Conductor: k (params holds eta)
  ClosureParam param2Kind;         // how `params2` is to be read
  uint32_t flags;                  // kClosureVariesWithWavelength
  float scalars[4];                // per-kind scalars (roughness, exponent); unused ones are 0
};
static_assert(offsetof(ClosureNode, params) == 20 && offsetof(ClosureNode, params2) == 52 &&
                  offsetof(ClosureNode, param2Kind) == 84 && offsetof(ClosureNode, flags) == 88 &&
                  offsetof(ClosureNode, scalars) == 92 && sizeof(ClosureNode) == 108,
              "ClosureNode layout is part of the ABI (docs/abi.md)");

// A bump arena the compiled code appends closure nodes to; a Material value is an index.
struct ClosureArena {
  ClosureNode* nodes;
  int32_t capacity;
  int32_t count;     // reset to 0 by the caller before each evaluation
  int32_t overflow;  // set when capacity was exceeded (the material is then invalid)
};

// Per-call context: the path's wavelengths (Spectrum lanes) and the closure arena.
struct ShadingContext {
  float lambdaNm[kMaxWavelengths];
  int32_t wavelengthCount;  // must equal the lane count the code was compiled for
  ClosureArena* arena;      // may be null if the code builds no Material
};

// The Hit record as flattened in argument buffers (fields in sorted name order).
struct HitAbi {
  float dpdx[3], dpdy[3], duvdx[2], duvdy[2], n[3], p[3], uv[2];
};
static_assert(sizeof(HitAbi) == 18 * 4, "Hit is 18 words");

// Every compiled entry point: reads its arguments from `args` and writes its result to
// `result`, both in the word layout of docs/abi.md.
using EntryFn = void (*)(const void* args, void* result, const ShadingContext* ctx);

}  // namespace tex::compiler
