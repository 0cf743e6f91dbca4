// Whether a material's closure tree can depend on its Hit: a conservative data-flow analysis
// over the typed core IR (lang/core_ir.h). The IR is first-order and pure, and a function's only
// inputs are its arguments and the context's wavelengths, so a result that no path of the data
// flow connects to the Hit parameter is a function of the wavelengths and the other arguments
// alone: the renderer may then reuse one evaluation for every hit of a wavelength group
// (material_memo.h). Calls are analysed per pattern of dependent arguments; recursion and
// anything unexpected count as dependent.
#pragma once
#include "lang/core_ir.h"

namespace tex::render {

// True if the result of `function` provably does not depend on its parameter `parameter`.
bool resultIgnoresParameter(const lang::ir::Program& program, int function, int parameter);

}  // namespace tex::render
