// Which material parameters depend on the wavelength: the static analysis behind the closure
// flag kClosureVariesWithWavelength (design contract 5: the compiler tells the renderer
// whether, e.g., an IOR is dispersive). The interpreter and the compiler both use it, so they
// set the same flags.
//
// A value depends on the wavelength if it is, or is computed from, `lambda_nm` (Prim::
// Wavelengths) or an entry parameter whose type holds a Spectrum (the caller may pass anything).
// Constants, splats of Floats and everything derived only from them do not. Only values whose
// type holds a Spectrum can depend: no builtin reduces a Spectrum to a Float, Color or Bool
// (spec 4.2), so `{s: lambda_nm, x: 1.5}.x` does not (revisit if such a builtin is added).
// Records count as one value otherwise (a field-insensitive, conservative choice).
//
// The analysis is context-sensitive: a function is analysed once per pattern of
// wavelength-dependent arguments (a "context"), so `glass(spectrum(1.5))` and
// `glass(cauchy(1.5, 4200.0))` flag the same dielectric node differently. Code generation
// emits one copy of a material-building function per context it is reached in.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "lang/core_ir.h"

namespace tex::lang::ir {

class WavelengthDependence {
 public:
  explicit WavelengthDependence(const Program& program) : program_(program) {}

  // Whether `function` (or anything it calls) builds a material leaf: only those functions
  // need contexts; for the others every context generates the same code.
  bool buildsMaterial(int function);
  // The context of `function` called as an entry point.
  int entryContext(int function);
  // The context in which the Call or Fold node `n` of context `context` runs its callee.
  int calleeContext(int context, const Node* n);
  int function(int context) const { return contexts_[size_t(context)]->function; }
  // MaterialNode / ClosureNode flags of the material-leaf node `n` evaluated in `context`.
  uint32_t flags(int context, const Node* n) const;

 private:
  struct Context {
    int function;
    std::vector<bool> params;  // which parameters depend on the wavelength
    bool resultDepends = false;
    bool done = false;
    std::map<const Node*, uint32_t> leafFlags;
    std::map<const Node*, int> callees;
  };
  int context(int function, std::vector<bool> params);
  bool walk(Context& c, const Node* n, std::vector<bool>& slots);
  bool walkNode(Context& c, const Node* n, std::vector<bool>& slots);
  bool canDepend(const Type* t);
  bool nodeBuildsMaterial(const Node* n);

  const Program& program_;
  std::map<std::pair<int, std::vector<bool>>, int> ids_;
  std::vector<std::unique_ptr<Context>> contexts_;
  std::map<int, bool> builds_;
  std::map<const Type*, bool> typeHoldsSpectrum_;
};

// Whether a value of this type can carry a wavelength dependence (a Spectrum, or a record or
// lambda capture holding one).
bool holdsSpectrum(const Type* t);

}  // namespace tex::lang::ir
