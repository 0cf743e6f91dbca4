#include "renderer/material/tex_binding.h"

#include <stdexcept>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "lang/lexer.h"
#include "lang/session.h"
#include "lang/types.h"
#include "renderer/material/closure_kinds.h"
#include "renderer/material/hit_dependence.h"

namespace tex::render {

namespace {

bool isIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(uint8_t(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(uint8_t(c)) || c == '_')) return false;
  return true;
}

std::string floatLiteral(float v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  std::string s = buf;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // a Float literal, not an Int
  if (s[0] == '-') s = "(" + s + ")";
  return s;
}

// The literal text of a constant parameter of type `type`, or an error.
bool literalFor(const lang::Type* type, const TexParamValue& v, std::string& text, std::string& why) {
  using K = lang::TypeKind;
  const auto vectorText = [&](const char* ctor, size_t n) {
    // A whole number (JSON 1, as many writers print 1.0) broadcasts like a Float.
    if (v.kind != TexParamValue::Kind::Vec && v.kind != TexParamValue::Kind::Float && v.kind != TexParamValue::Kind::Int)
      return false;
    std::vector<float> f = v.kind == TexParamValue::Kind::Int ? std::vector<float>{float(v.intValue)} : v.floats;
    if (f.size() == 1) f.assign(n, f[0]);
    if (f.size() != n) return false;
    text = std::string(ctor) + "(";
    for (size_t i = 0; i < n; ++i) text += (i ? ", " : "") + floatLiteral(f[i]);
    text += ")";
    return true;
  };
  switch (type->kind) {
    case K::Bool:
      if (v.kind != TexParamValue::Kind::Bool) break;
      text = v.boolValue ? "true" : "false";
      return true;
    case K::Int:
      if (v.kind == TexParamValue::Kind::Int) {
        text = std::to_string(v.intValue);
        if (v.intValue < 0) text = "(" + text + ")";
        return true;
      }
      break;
    case K::Float:
      if (v.kind == TexParamValue::Kind::Float || v.kind == TexParamValue::Kind::Int) {
        text = floatLiteral(v.kind == TexParamValue::Kind::Int ? float(v.intValue) : v.floats.at(0));
        return true;
      }
      break;
    case K::Vec2: if (vectorText("vec2", 2)) return true; break;
    case K::Vec3: if (vectorText("vec3", 3)) return true; break;
    case K::Vec4: if (vectorText("vec4", 4)) return true; break;
    case K::Color:
      if (vectorText("rgb", 3)) return true;
      if (v.kind == TexParamValue::Kind::Spectrum && v.spectrum.kind == SpectrumDesc::Kind::Rgb) {
        const Vec3 c = v.spectrum.rgb * v.spectrum.scale;
        text = "rgb(" + floatLiteral(c.x) + ", " + floatLiteral(c.y) + ", " + floatLiteral(c.z) + ")";
        return true;
      }
      break;
    default:
      break;
  }
  why = "a value of type " + lang::typeName(type) + " is needed";
  return false;
}

// A Spectrum parameter's value as a source: numbers are constant spectra, three numbers an RGB
// (anything else, such as a Bool or two numbers, is an error: it used to render black).
SpectrumSource spectrumArgument(const TexParamValue& v) {
  SpectrumDesc d;
  if (v.kind == TexParamValue::Kind::Spectrum) {
    d = v.spectrum;
  } else if (v.kind == TexParamValue::Kind::Vec && v.floats.size() == 3) {
    d.kind = SpectrumDesc::Kind::Rgb;
    d.rgb = Vec3(v.floats[0], v.floats[1], v.floats[2]);
  } else if (v.kind == TexParamValue::Kind::Int || (v.kind == TexParamValue::Kind::Float && v.floats.size() == 1)) {
    d.kind = SpectrumDesc::Kind::Constant;
    d.value = v.kind == TexParamValue::Kind::Int ? float(v.intValue) : v.floats[0];
  } else {
    throw std::invalid_argument("a Spectrum is needed: a number, [r, g, b] or a spectrum object");
  }
  switch (d.rgbAs) {
    case SpectrumDesc::RgbAs::Reflectance: return SpectrumSource(d, SpectrumUse::Reflectance);
    case SpectrumDesc::RgbAs::Unbounded: return SpectrumSource(d, SpectrumUse::Unbounded);
    case SpectrumDesc::RgbAs::Illuminant: return SpectrumSource(d, SpectrumUse::Illuminant);
    case SpectrumDesc::RgbAs::ByValue: break;
  }
  // RGB inside the unit cube reads as a reflectance (bounded by 1); beyond it, as an
  // unbounded quantity (an IOR, a radiance given in RGB). An emission wants "as": "illuminant".
  const bool bounded = d.kind != SpectrumDesc::Kind::Rgb || (d.rgb.x <= 1 && d.rgb.y <= 1 && d.rgb.z <= 1);
  return SpectrumSource(d, bounded ? SpectrumUse::Reflectance : SpectrumUse::Unbounded);
}

compiler::CompileOptions materialCompileOptions(int wavelengths, bool quick, bool useCache) {
  compiler::CompileOptions options;
  options.opt = quick ? compiler::OptLevel::Quick : compiler::OptLevel::O1;
  options.wavelengths = wavelengths;
  options.useCache = useCache;
  return options;
}

std::string renderedDiagnostics(lang::Session& session) {
  std::string s;
  for (const lang::Diagnostic& d : session.diags().items()) s += lang::renderDiagnostic(d);
  return s;
}

}  // namespace

bool compileGltfMaterial(int wavelengths, bool quick, bool useCache, CompiledGltf& out, std::string& error) {
  const auto start = std::chrono::steady_clock::now();
  lang::Session session;
  lang::ModuleInfo* module = session.loadSource(
      "<gltf material>", "import std.gltf.{metallic_roughness_anisotropic}\n"
                         "export fn gltf_material(h: Hit, base: Color, metallic: Float, roughness: Float, "
                         "transmission: Float, ior: Float, dispersion: Float, thin_walled: Float, emission_rgb: Color, "
                         "clearcoat: Float, clearcoat_roughness: Float, sheen_color: Color, sheen_roughness: Float, "
                         "specular: Float, specular_color: Color, anisotropy: Float, anisotropy_rotation: Float) -> Material =\n"
                         "  metallic_roughness_anisotropic(h, base, metallic, roughness, transmission, ior, dispersion, thin_walled > 0.5, "
                         "emission_rgb, clearcoat, clearcoat_roughness, sheen_color, sheen_roughness, specular, specular_color, "
                         "anisotropy, anisotropy_rotation)\n");
  auto& types = lang::TypeTable::global();
  int fn = -1;
  if (module && !session.diags().hasErrors())
    fn = session.instantiate(module, "gltf_material",
                             {types.hit(), types.color(), types.floating(), types.floating(), types.floating(),
                              types.floating(), types.floating(), types.floating(), types.color(), types.floating(),
                              types.floating(), types.color(), types.floating(), types.floating(), types.color(),
                              types.floating(), types.floating()},
                             {});
  const compiler::CompileOptions options = materialCompileOptions(wavelengths, quick, useCache);
  if (fn >= 0 && !session.diags().hasErrors()) out.module = compiler::compile(session.program(), {fn}, options, session.diags());
  if (!out.module) {
    error = "std.gltf: " + renderedDiagnostics(session);
    return false;
  }
  out.entry = out.module->entry(fn);
  out.hitIndependent = resultIgnoresParameter(session.program(), fn, 0);
  out.compileMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return true;
}

bool compileBindings(const SceneDescription& scene, int wavelengths, bool quick, bool useCache,
                     CompiledBindings& out, std::string& error) {
  out = CompiledBindings();
  if (scene.texMaterials.empty()) return true;
  const auto start = std::chrono::steady_clock::now();
  lang::Session session;
  std::vector<int> entries;
  std::vector<CompiledBinding> bindings;
  std::string problems;
  for (size_t i = 0; i < scene.texMaterials.size(); ++i) {
    const TexMaterialBinding& b = scene.texMaterials[i];
    const std::string where = b.origin.empty() ? scene.sourcePath : b.origin;
    const std::filesystem::path file(b.file);
    const std::string stem = file.stem().string();
    // The binding imports the file as a module by its name, which finds `stem.tex` beside it:
    // another extension loaded one file and rendered another (wall.mat bound, wall.tex used).
    if (file.extension() != ".tex") {
      problems += where + ": error: material file '" + b.file + "' must be a .tex module\n";
      continue;
    }
    if (!isIdentifier(stem) || lang::isKeyword(stem)) {
      problems += where + ": error: material file name '" + file.filename().string() + "' must be a module name (letters, digits, _; " +
                  "not a keyword such as 'type'), so that it can be imported\n";
      continue;
    }
    lang::ModuleInfo* module = session.loadFile(b.file);
    if (!module) {
      problems += where + ": error: cannot read material file '" + b.file + "'\n";
      continue;
    }
    if (session.diags().hasErrors()) break;
    const lang::FunctionDecl* decl = session.findFunction(module, b.entry);
    std::vector<const lang::Type*> paramTypes;
    const lang::Type* resultType = nullptr;
    if (!decl || !session.signature(decl, paramTypes, resultType)) {
      problems += where + ": error: '" + b.file + "' has no exported, annotated function '" + b.entry + "'\n";
      continue;
    }
    if (!decl->item->exported) {  // else the generated wrapper's import fails, naming itself
      problems += where + ": error: '" + b.file + "' defines '" + b.entry + "' but does not export it (write `export fn " +
                  b.entry + "`)\n";
      continue;
    }
    const auto& params = decl->item->params;
    if (paramTypes.empty() || paramTypes[0] != lang::TypeTable::global().hit() || !resultType ||
        resultType->kind != lang::TypeKind::Material) {
      problems += where + ": error: material '" + b.entry + "' must have the type (h: Hit, ...) -> Material\n";
      continue;
    }
    CompiledBinding cb;
    cb.name = file.filename().string() + ":" + b.entry;
    std::string wrapperParams = "h: Hit", callArgs = "h";
    bool ok = true;
    for (const auto& [name, value] : b.params) {
      bool known = false;
      for (size_t p = 1; p < params.size(); ++p) known = known || params[p].name == name;
      if (!known) {
        std::string names;
        for (size_t p = 1; p < params.size(); ++p) names += (names.empty() ? "" : ", ") + params[p].name;
        problems += where + ": error: material '" + b.entry + "' has no parameter '" + name + "' (it has: " +
                    (names.empty() ? "none" : names) + ")\n";
        ok = false;
      }
    }
    for (size_t p = 1; p < params.size() && ok; ++p) {
      auto it = b.params.find(params[p].name);
      if (it == b.params.end()) {
        if (!params[p].defaultValue) {
          problems += where + ": error: material '" + b.entry + "' needs a value for parameter '" + params[p].name + "'\n";
          ok = false;
        }
        continue;
      }
      const lang::Type* t = paramTypes[p];
      if (t->kind == lang::TypeKind::Spectrum) {
        const std::string local = "p" + std::to_string(cb.spectrumArgs.size());
        wrapperParams += ", " + local + ": Spectrum";
        callArgs += ", " + params[p].name + ": " + local;
        try {
          cb.spectrumArgs.push_back(spectrumArgument(it->second));
        } catch (const std::exception& e) {
          problems += where + ": error: parameter '" + params[p].name + "' of material '" + b.entry + "': " + e.what() + "\n";
          ok = false;
        }
        continue;
      }
      std::string literal, why;
      if (!literalFor(t, it->second, literal, why)) {
        problems += where + ": error: parameter '" + params[p].name + "' of material '" + b.entry + "': " + why + "\n";
        ok = false;
        continue;
      }
      callArgs += ", " + params[p].name + ": " + literal;
    }
    if (!ok) continue;
    const std::string wrapperPath = (file.parent_path() / ("__scene_binding_" + std::to_string(i) + ".tex")).string();
    const std::string text = "import " + stem + " as material_module\n" + "export fn binding(" + wrapperParams +
                             ") -> Material = material_module." + b.entry + "(" + callArgs + ")\n";
    lang::ModuleInfo* wrapper = session.loadSource(wrapperPath, text);
    if (!wrapper || session.diags().hasErrors()) break;
    std::vector<const lang::Type*> argTypes{paramTypes[0]};
    for (size_t k = 0; k < cb.spectrumArgs.size(); ++k) argTypes.push_back(lang::TypeTable::global().spectrum());
    const int fn = session.instantiate(wrapper, "binding", argTypes, {});
    if (fn < 0 || session.diags().hasErrors()) break;
    entries.push_back(fn);
    bindings.push_back(std::move(cb));
  }
  if (session.diags().hasErrors() || !problems.empty()) {
    error = problems + renderedDiagnostics(session);
    return false;
  }
  for (size_t i = 0; i < bindings.size(); ++i) {
    bindings[i].hitIndependent = resultIgnoresParameter(session.program(), entries[i], 0);
    bindings[i].mayBuildThinWall = mayBuildPrimitive(session.program(), entries[i], lang::ir::Prim::MatThinDielectric);
  }
  const compiler::CompileOptions options = materialCompileOptions(wavelengths, quick, useCache);
  out.module = compiler::compile(session.program(), entries, options, session.diags());
  if (!out.module) {
    error = renderedDiagnostics(session);
    return false;
  }
  for (size_t i = 0; i < bindings.size(); ++i) bindings[i].entry = out.module->entry(entries[i]);
  out.bindings = std::move(bindings);
  out.cacheHit = out.module->stats().cacheHit;
  out.compileMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return true;
}

}  // namespace tex::render
