// Calling a compiled .tex material at a shading point and turning the closure tree it returns
// (compiler/abi.h, docs/abi.md "Materials") into native lobes and emitted radiance: mix weights
// multiply down the tree, Color parameters are upsampled to spectra (reflectances for lobes,
// illuminants for emission), Spectrum parameters are already per wavelength.
#pragma once
#include <array>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/material/material_system.h"
#include "renderer/material/tex_binding.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

struct ClosureEvaluation {
  bool ok = true;           // false: arena overflow, an unknown closure kind, or too many lobes
  bool sawEmission = false; // the tree holds an emission closure (even a black one)
};

// Calls a compiled material entry with the point's Hit followed by `extraWords` argument words,
// and walks the closure tree it returns into `bsdf`'s lobes and `emission` (bsdf null: the
// emission alone, for area lights).
ClosureEvaluation evaluateEntry(compiler::EntryFn entry, const float* extraArgs, int extraWords, const ShadingPoint& point,
                                const Wavelengths& lambda, Bsdf* bsdf, Spectrum& emission);

ClosureEvaluation evaluateBinding(const CompiledBinding& binding, const ShadingPoint& point, const Wavelengths& lambda,
                                  Bsdf* bsdf, Spectrum& emission);

// A Color parameter fitted for each of its uses (rgb_spectrum.h); the walk picks the one it
// upsamples with.
struct FittedColor {
  SigmoidPolynomial reflectance;
  RgbUnbounded unbounded;  // as an unbounded quantity and as an illuminant
};

// The closure tree of a material that depends on neither its Hit (CompiledBinding::
// hitIndependent) nor the wavelengths: no node carries kClosureVariesWithWavelength, and Floats,
// Colors and Bools never depend on the wavelength (docs/abi.md, lang/wavelength_dependence.h),
// so the mix weights, scalars, Color parameters and the tree's shape are the same for every
// wavelength group. Walking it at a group's wavelengths gives what evaluating the binding there
// gives, without calling the compiled code (its arguments, the JIT call, the node appends).
struct ConstantClosure {
  std::vector<compiler::ClosureNode> nodes;
  // Per node, its two parameter vectors' colours (params, params2) fitted once: the walk at
  // each wavelength group only evaluates the sigmoids (for Color parameters).
  std::vector<std::array<FittedColor, 2>> fitted;
  int32_t root = -1;
  int wavelengthCount = 0;  // the group size it was built for (lanes of Spectrum parameters)
};
// Evaluates the binding once at these wavelengths and keeps its tree if it is constant as
// above; false (tree empty) otherwise.
bool captureConstantClosure(const CompiledBinding& binding, const ShadingPoint& point, const Wavelengths& lambda,
                            ConstantClosure& tree);
// evaluateBinding for a captured tree at wavelengths of the group size it was built for.
ClosureEvaluation walkConstantClosure(const ConstantClosure& tree, const Wavelengths& lambda, Bsdf* bsdf,
                                      Spectrum& emission);

}  // namespace tex::render
