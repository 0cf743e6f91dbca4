// Calling a compiled .tex material at a shading point and turning the closure tree it returns
// (compiler/abi.h, docs/abi.md "Materials") into native lobes and emitted radiance: mix weights
// multiply down the tree, Color parameters are upsampled to spectra (reflectances for lobes,
// illuminants for emission), Spectrum parameters are already per wavelength.
#pragma once
#include "renderer/bsdf/bsdf.h"
#include "renderer/material/material_system.h"
#include "renderer/material/tex_binding.h"

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

}  // namespace tex::render
