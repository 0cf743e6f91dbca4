// Compiling the .tex materials a scene file binds (TexMaterialBinding) into one JIT module.
// Each binding becomes a small generated wrapper module next to the material's file:
//   import <stem> as m
//   export fn binding(h: Hit, <Spectrum parameters>) -> Material = m.<entry>(h, name: value, ...)
// so named arguments, defaults and type checking are the language's own, constant parameters
// (Bool, Int, Float, vectors, colours) are folded by the compiler, and Spectrum-valued
// parameters stay run-time arguments evaluated at each hit's wavelengths.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "compiler/abi.h"
#include "compiler/jit.h"
#include "renderer/scene/scene_description.h"
#include "renderer/spectra/spectrum_desc.h"

namespace tex::render {

struct CompiledBinding {
  compiler::EntryFn entry = nullptr;
  std::vector<SpectrumSource> spectrumArgs;  // after the Hit, in order, one Spectrum each
  std::string name;                          // "file.tex:entry", for messages
  // The closure tree provably does not depend on the Hit (hit_dependence.h): it is a function
  // of the wavelengths alone, and one evaluation serves every hit of a wavelength group.
  bool hitIndependent = false;
  // The closure tree may hold a thin wall (closure_kinds.h), which straight rays pass.
  bool mayBuildThinWall = false;
};

struct CompiledBindings {
  std::unique_ptr<compiler::CompiledModule> module;
  std::vector<CompiledBinding> bindings;  // parallel to SceneDescription::texMaterials
  double compileMs = 0;
  bool cacheHit = false;
};

// std.gltf.metallic_roughness_anisotropic compiled on its own: the material of every glTF
// material that no binding overrides. Its arguments after the Hit are GltfInputs' fields in order
// (renderer/material/gltf_material.h): 3 + 6 + 3 + 2 + 3 + 1 + 1 + 3 + 2 = 24 words.
struct CompiledGltf {
  std::unique_ptr<compiler::CompiledModule> module;
  compiler::EntryFn entry = nullptr;
  bool hitIndependent = false;  // std.gltf reads only its inputs, not the Hit (hit_dependence.h)
  double compileMs = 0;
};
inline constexpr int kGltfArgumentWords = 24;
bool compileGltfMaterial(int wavelengths, bool quick, bool useCache, CompiledGltf& out, std::string& error);

// Returns false with rendered diagnostics in `error`.
bool compileBindings(const SceneDescription& scene, int wavelengths, bool quick, bool useCache,
                     CompiledBindings& out, std::string& error);

}  // namespace tex::render
