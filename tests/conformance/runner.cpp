// Runs conformance programs (docs/language.md section 8): checks each file's expected value
// and type, or its exact set of diagnostics. Usage: conformance_runner DIR|FILE... [-v]
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/jit.h"
#include "compiler/value_layout.h"
#include "renderer/spectra/rgb_spectrum.h"
#include "lang/interpreter.h"
#include "lang/session.h"

namespace fs = std::filesystem;
using namespace tex::lang;

namespace {

int jitComparisons = 0;  // compiled runs compared with the interpreter

struct Expectation {
  bool hasValue = false;
  bool approximate = false;
  std::string value, type;
  std::set<std::string> errors;  // "E0401 @ 3:14" (or "E0401 @ file.tex:3:14")
  std::string entry = "main";
  bool isTest() const { return hasValue || !errors.empty(); }
};

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r' || s.back() == '\t')) s.pop_back();
  size_t i = s.find_first_not_of(" \t");
  return i == std::string::npos ? "" : s.substr(i);
}

bool readExpectation(const std::string& text, Expectation& x, std::string& problem) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.rfind("//", 0) != 0) continue;
    std::string body = trim(line.substr(2));
    auto take = [&](const char* key, std::string& rest) {
      size_t n = std::string(key).size();
      if (body.compare(0, n, key) != 0) return false;
      rest = trim(body.substr(n));
      return true;
    };
    std::string rest;
    if (take("expect:", rest)) {
      size_t colon = rest.rfind(" : ");
      if (colon == std::string::npos) {
        problem = "malformed 'expect:' line (want 'expect: VALUE : TYPE'): " + line;
        return false;
      }
      x.hasValue = true;
      x.value = trim(rest.substr(0, colon));
      x.type = trim(rest.substr(colon + 3));
      if (!x.value.empty() && x.value[0] == '~') {
        x.approximate = true;
        x.value = trim(x.value.substr(1));
      }
    } else if (take("error:", rest)) {
      std::string code, at, where;
      std::istringstream parts(rest);
      parts >> code >> at >> where;
      if (at != "@" || where.empty()) {
        problem = "malformed 'error:' line (want 'error: CODE @ LINE:COL'): " + line;
        return false;
      }
      x.errors.insert(code + " @ " + where);
    } else if (take("entry:", rest)) {
      x.entry = rest;
    }
  }
  return true;
}

bool approximatelyEqual(const std::string& got, const std::string& want) {
  char* end = nullptr;
  double w = std::strtod(want.c_str(), &end);
  if (end == want.c_str()) return false;
  double g = std::strtod(got.c_str(), &end);
  if (end == got.c_str()) return false;
  if (std::isnan(w)) return std::isnan(g);
  return std::fabs(g - w) <= 1e-5 * std::max(1.0, std::fabs(w));
}

// The floating-point contract of docs/language.md section 5, as the differential tests use
// it: + - * / sqrt agree exactly; transcendentals within 4 ulp. Lane by lane: identical bits,
// both NaN, or at most 4 units in the last place apart.
bool floatsAgree(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return std::signbit(a) == std::signbit(b) || a != 0;
  if (std::isinf(a) || std::isinf(b)) return false;
  auto ordered = [](float f) {
    int32_t i;
    std::memcpy(&i, &f, 4);
    return i < 0 ? int64_t(INT32_MIN) - i : int64_t(i);
  };
  return std::llabs(ordered(a) - ordered(b)) <= 4;
}

bool valuesAgree(const Value& a, const Value& b, const Type* t, int lanes) {
  switch (t->kind) {
    case TypeKind::Bool: return (a.i != 0) == (b.i != 0);
    case TypeKind::Int:
    case TypeKind::Image: return a.i == b.i;  // an Image is its handle in the image table
    case TypeKind::Material: {
      WavelengthGroup g;
      g.count = lanes;
      return formatValue(a, t, g) == formatValue(b, t, g);
    }
    case TypeKind::Record:
    case TypeKind::Lambda:
      for (size_t i = 0; i < t->fields.size(); ++i)
        if (!valuesAgree((*a.fields)[i], (*b.fields)[i], t->fields[i].second, lanes)) return false;
      return true;
    default: {
      int n = t->kind == TypeKind::Spectrum ? lanes : t->fixedLanes();
      for (int i = 0; i < n; ++i)
        if (!floatsAgree(a.f[i], b.f[i])) return false;
      return true;
    }
  }
}

bool containsSpectrum(const Type* t) {
  if (t->kind == TypeKind::Spectrum) return true;
  for (auto& f : t->fields)
    if (containsSpectrum(f.second)) return true;
  return false;
}

// Runs `fn` compiled at `opt` with `lanes` wavelengths; compares with the interpreter.
std::string differential(Session& session, int fn, tex::compiler::OptLevel opt, int lanes) {
  tex::compiler::CompileOptions options;
  options.opt = opt;
  options.wavelengths = lanes;
  options.useCache = false;
  Diagnostics diags;
  auto module = tex::compiler::compile(session.program(), {fn}, options, diags);
  const char* mode = opt == tex::compiler::OptLevel::Quick ? "quick" : "O1";
  if (!module) {
    std::string all;
    for (auto& d : diags.items()) all += renderDiagnostic(d);
    return std::string("JIT (") + mode + ") failed:\n" + all;
  }
  WavelengthGroup group;
  group.count = lanes;
  tex::compiler::ShadingContext ctx{};
  for (int i = 0; i < lanes; ++i) ctx.lambdaNm[i] = group.lambdaNm[i] = 400.0f + 100.0f * float(i) / (lanes == 8 ? 2 : 1);
  ctx.wavelengthCount = lanes;
  std::vector<tex::compiler::ClosureNode> nodes(256);
  tex::compiler::ClosureArena arena{nodes.data(), int32_t(nodes.size()), 0, 0};
  ctx.arena = &arena;
  const Type* resultType = session.program().functions[size_t(fn)].resultType;
  std::vector<uint32_t> result(tex::compiler::wordCount(resultType, lanes) + 1, 0);
  module->entry(fn)(nullptr, result.data(), &ctx);
  ++jitComparisons;
  Value jit = tex::compiler::unflatten(result.data(), resultType, lanes, &arena);
  Value interp = evaluate(session.program(), fn, {}, group);
  if (valuesAgree(jit, interp, resultType, lanes)) return {};
  return std::string("JIT (") + mode + ", " + std::to_string(lanes) + " wavelengths) disagrees with the interpreter:\n  jit    " +
         formatValue(jit, resultType, group) + "\n  interp " + formatValue(interp, resultType, group);
}

// Returns an empty string on success, else what went wrong.
std::string runOne(const fs::path& file, const Expectation& x) {
  Session session;
  ModuleInfo* module = session.loadFile(file.string());
  std::set<std::string> got;
  std::string rendered;
  for (const Diagnostic& d : session.diags().items()) {
    if (d.severity != Severity::Error) continue;
    rendered += renderDiagnostic(d);
    if (!d.span.file) {
      got.insert(d.code + " @ ?");
      continue;
    }
    auto lc = d.span.file->lineCol(d.span.begin);
    std::string pos = std::to_string(lc.line) + ":" + std::to_string(lc.col);
    bool sameFile = fs::path(d.span.file->path).filename() == file.filename();
    got.insert(d.code + " @ " + (sameFile ? pos : fs::path(d.span.file->path).filename().string() + ":" + pos));
  }
  if (!x.errors.empty()) {
    if (got == x.errors) return {};
    std::string s = "expected diagnostics:";
    for (auto& e : x.errors) s += " [" + e + "]";
    s += "\n  got:";
    for (auto& e : got) s += " [" + e + "]";
    return s + "\n" + rendered;
  }
  if (!got.empty() || !module) return "unexpected diagnostics:\n" + rendered;
  int fn = session.instantiate(module, x.entry, {}, Span{});
  if (fn < 0 || session.diags().hasErrors()) {
    std::string all;
    for (auto& d : session.diags().items()) all += renderDiagnostic(d);
    return "cannot instantiate '" + x.entry + "()':\n" + all;
  }
  const ir::Function& f = session.program().functions[size_t(fn)];
  WavelengthGroup group;
  Value v = evaluate(session.program(), fn, {}, group);
  std::string value = formatValue(v, f.resultType, group);
  std::string type = typeName(f.resultType);
  bool valueOk = x.approximate ? approximatelyEqual(value, x.value) : value == x.value;
  if (valueOk && type == x.type) {
    // Differential testing: the JIT at both levels must agree with the interpreter.
    for (auto opt : {tex::compiler::OptLevel::Quick, tex::compiler::OptLevel::O1}) {
      std::string problem = differential(session, fn, opt, 4);
      if (!problem.empty()) return problem;
    }
    if (containsSpectrum(f.resultType)) {
      std::string problem = differential(session, fn, tex::compiler::OptLevel::O1, 8);
      if (!problem.empty()) return problem;
    }
    return {};
  }
  return "expected " + std::string(x.approximate ? "~" : "") + x.value + " : " + x.type + "\n  got      " + value + " : " + type;
}

}  // namespace

int main(int argc, char** argv) {
  tex::render::installRgbUpsampling();  // reflectance_spectrum & co. use the renderer's table
  std::vector<fs::path> files;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "-v") {
      verbose = true;
      continue;
    }
    if (fs::is_directory(a)) {
      for (auto& entry : fs::recursive_directory_iterator(a))
        if (entry.path().extension() == ".tex") files.push_back(entry.path());
    } else {
      files.push_back(a);
    }
  }
  std::sort(files.begin(), files.end());
  int passed = 0, failed = 0;
  for (const fs::path& file : files) {
    std::string text, err;
    if (!readFile(file.string(), text, err)) {
      std::printf("FAIL %s: %s\n", file.c_str(), err.c_str());
      ++failed;
      continue;
    }
    Expectation x;
    std::string problem;
    if (!readExpectation(text, x, problem)) {
      std::printf("FAIL %s: %s\n", file.c_str(), problem.c_str());
      ++failed;
      continue;
    }
    if (!x.isTest()) continue;  // a helper module imported by tests
    std::string result = runOne(file, x);
    if (result.empty()) {
      ++passed;
      if (verbose) std::printf("ok   %s\n", file.c_str());
    } else {
      ++failed;
      std::printf("FAIL %s\n  %s\n", file.c_str(), result.c_str());
    }
  }
  std::printf("(%d JIT runs agreed with the interpreter)\n", jitComparisons);
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed == 0 && passed > 0 ? 0 : 1;
}
