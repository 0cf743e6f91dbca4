// Material closures built by compiled code: dielectric and conductor lobes, the
// wavelength-dependence flag, mix weights and arena overflow, the layered/scaled/added kinds
// and the sheen with their scalars, at 4 and 8 wavelengths, against the interpreter's tree; and
// the std.spectra / std.materials formulas.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "compiler/jit.h"
#include "compiler/value_layout.h"
#include "lang/interpreter.h"
#include "lang/session.h"
#include "renderer/color/color.h"
#include "renderer/spectra/spectrum_desc.h"

using namespace tex;
using namespace tex::lang;
using compiler::ClosureKind;
using compiler::ClosureNode;
using compiler::ClosureParam;

namespace {

// eta is an entry parameter of type Spectrum: the caller may pass anything, so the conductor
// is flagged as varying unless eta is specialised to a constant.
const char* kSource =
    "import std.spectra.{cauchy}\n"
    "export fn m(h: Hit, eta: Spectrum) -> Material =\n"
    "  mix_material(mix_material(dielectric(cauchy(1.5, 4200.0)), dielectric(1.5), h.uv.x),\n"
    "               conductor(eta, rgb(3.0, 2.5, 2.0)), 0.25)\n";

struct Fixture {
  Session session;
  int fn = -1;
  Fixture() {
    ModuleInfo* m = session.loadSource("closure.tex", kSource);
    auto& types = TypeTable::global();
    if (m) fn = session.instantiate(m, "m", {types.hit(), types.spectrum()}, Span{});
    for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  }
};

WavelengthGroup groupOf(int lanes) {
  WavelengthGroup g;
  g.count = lanes;
  for (int i = 0; i < lanes; ++i) g.lambdaNm[i] = 412.5f + 37.0f * float(i);  // not the default group
  return g;
}

compiler::ShadingContext contextOf(const WavelengthGroup& g, compiler::ClosureArena* arena) {
  compiler::ShadingContext ctx{};
  for (int i = 0; i < g.count; ++i) ctx.lambdaNm[i] = g.lambdaNm[i];
  ctx.wavelengthCount = g.count;
  ctx.arena = arena;
  return ctx;
}

Value etaValue(int lanes) {
  Value eta;
  for (int i = 0; i < lanes; ++i) eta.f[i] = 0.2f + 0.01f * float(i);
  return eta;
}

std::vector<uint32_t> argWords(const Value& hit, const Value& eta, int lanes) {
  std::vector<uint32_t> words;
  compiler::flatten(hit, TypeTable::global().hit(), lanes, words);
  compiler::flatten(eta, TypeTable::global().spectrum(), lanes, words);
  return words;
}

class ClosureLanes : public ::testing::TestWithParam<int> {};

// `m(h: Hit, w: Spectrum) -> Material` of a source, compiled for `lanes` wavelengths and run at
// one hit into an arena of `capacity` nodes, with the interpreter's tree for the same inputs.
struct BuiltTree {
  Session session;
  int fn = -1;
  std::unique_ptr<compiler::CompiledModule> module;
  WavelengthGroup group;
  Value hit, w;
  std::vector<ClosureNode> nodes;
  compiler::ClosureArena arena{};
  int32_t root = -1;
  Value interp;                    // the interpreter's tree
  std::string jitText, interpText;  // both trees as formatValue prints them
};

void buildTree(BuiltTree& t, const char* file, const std::string& source, int lanes, size_t capacity) {
  auto& types = TypeTable::global();
  ModuleInfo* mod = t.session.loadSource(file, source);
  t.fn = mod ? t.session.instantiate(mod, "m", {types.hit(), types.spectrum()}, Span{}) : -1;
  for (auto& d : t.session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(t.fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  options.wavelengths = lanes;
  t.module = compiler::compile(t.session.program(), {t.fn}, options, t.session.diags());
  ASSERT_NE(t.module, nullptr);
  t.group = groupOf(lanes);
  t.nodes.resize(capacity);
  t.arena = compiler::ClosureArena{t.nodes.data(), int32_t(capacity), 0, 0};
  compiler::ShadingContext ctx = contextOf(t.group, &t.arena);
  t.hit = makeHit(0.125f, 0.375f);
  t.w = etaValue(lanes);
  std::vector<uint32_t> args = argWords(t.hit, t.w, lanes);
  t.module->entry(t.fn)(args.data(), &t.root, &ctx);
  ASSERT_EQ(t.arena.overflow, 0);
  ASSERT_GE(t.root, 0);
  t.interp = evaluate(t.session.program(), t.fn, {t.hit, t.w}, t.group);
  Value jit = compiler::unflatten(reinterpret_cast<const uint32_t*>(&t.root), types.material(), lanes, &t.arena);
  ASSERT_TRUE(t.interp.material && jit.material);
  t.jitText = formatValue(jit, types.material(), t.group);
  t.interpText = formatValue(t.interp, types.material(), t.group);
}

TEST_P(ClosureLanes, JitBuildsTheTreeTheInterpreterBuilds) {
  const int lanes = GetParam();
  Fixture f;
  ASSERT_GE(f.fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  options.wavelengths = lanes;
  auto module = compiler::compile(f.session.program(), {f.fn}, options, f.session.diags());
  ASSERT_NE(module, nullptr);

  WavelengthGroup group = groupOf(lanes);
  std::vector<ClosureNode> nodes(16);
  compiler::ClosureArena arena{nodes.data(), int32_t(nodes.size()), 0, 0};
  compiler::ShadingContext ctx = contextOf(group, &arena);
  Value hit = makeHit(0.75f, 0.5f);
  Value eta = etaValue(lanes);
  std::vector<uint32_t> args = argWords(hit, eta, lanes);
  int32_t root = -1;
  module->entry(f.fn)(args.data(), &root, &ctx);
  ASSERT_EQ(arena.overflow, 0);
  ASSERT_EQ(arena.count, 5);
  ASSERT_GE(root, 0);

  const ClosureNode& top = nodes[size_t(root)];
  ASSERT_EQ(top.kind, ClosureKind::Mix);
  EXPECT_EQ(top.weight, 0.25f);
  EXPECT_EQ(top.flags, 0u);
  const ClosureNode& inner = nodes[size_t(top.a)];
  ASSERT_EQ(inner.kind, ClosureKind::Mix);
  EXPECT_EQ(inner.weight, 0.75f);  // h.uv.x

  const ClosureNode& dispersive = nodes[size_t(inner.a)];
  ASSERT_EQ(dispersive.kind, ClosureKind::Dielectric);
  EXPECT_EQ(dispersive.paramKind, ClosureParam::Spectrum);
  EXPECT_EQ(dispersive.flags, compiler::kClosureVariesWithWavelength);
  for (int i = 0; i < lanes; ++i) {
    float lambda = group.lambdaNm[i];
    EXPECT_EQ(dispersive.params[i], 1.5f + 4200.0f / (lambda * lambda)) << "lane " << i;
  }
  EXPECT_GT(dispersive.params[0], dispersive.params[lanes - 1]);  // normal dispersion

  const ClosureNode& constant = nodes[size_t(inner.b)];
  ASSERT_EQ(constant.kind, ClosureKind::Dielectric);
  EXPECT_EQ(constant.flags, 0u);
  for (int i = 0; i < lanes; ++i) EXPECT_EQ(constant.params[i], 1.5f);

  const ClosureNode& metal = nodes[size_t(top.b)];
  ASSERT_EQ(metal.kind, ClosureKind::Conductor);
  EXPECT_EQ(metal.paramKind, ClosureParam::Spectrum);
  EXPECT_EQ(metal.param2Kind, ClosureParam::Color);
  EXPECT_EQ(metal.flags, compiler::kClosureVariesWithWavelength);
  for (int i = 0; i < lanes; ++i) EXPECT_EQ(metal.params[i], eta.f[i]);
  EXPECT_EQ(metal.params2[0], 3.0f);
  EXPECT_EQ(metal.params2[1], 2.5f);
  EXPECT_EQ(metal.params2[2], 2.0f);

  // The interpreter builds the same tree, flags included.
  Value interp = evaluate(f.session.program(), f.fn, {hit, eta}, group);
  Value jit = compiler::unflatten(reinterpret_cast<const uint32_t*>(&root), TypeTable::global().material(), lanes, &arena);
  ASSERT_TRUE(interp.material && jit.material);
  const Type* material = TypeTable::global().material();
  EXPECT_EQ(formatValue(jit, material, group), formatValue(interp, material, group));
  const MaterialNode* interpDispersive = interp.material->a->a.get();
  ASSERT_EQ(interpDispersive->kind, MaterialNode::Kind::Dielectric);
  EXPECT_EQ(interpDispersive->flags, kMaterialVariesWithWavelength);
  EXPECT_EQ(interp.material->a->b->flags, 0u);
  EXPECT_EQ(interp.material->b->flags, kMaterialVariesWithWavelength);
}

TEST_P(ClosureLanes, ArenaOverflowIsReportedNotACrash) {
  const int lanes = GetParam();
  Fixture f;
  ASSERT_GE(f.fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  options.wavelengths = lanes;
  auto module = compiler::compile(f.session.program(), {f.fn}, options, f.session.diags());
  ASSERT_NE(module, nullptr);
  WavelengthGroup group = groupOf(lanes);
  std::vector<uint32_t> args = argWords(makeHit(0.5f, 0.5f), etaValue(lanes), lanes);
  // Three of the five nodes fit; the guard node after them must stay untouched.
  std::vector<ClosureNode> nodes(4);
  nodes[3].kind = ClosureKind(77);
  compiler::ClosureArena arena{nodes.data(), 3, 0, 0};
  compiler::ShadingContext ctx = contextOf(group, &arena);
  int32_t root = 0;
  module->entry(f.fn)(args.data(), &root, &ctx);
  EXPECT_EQ(arena.overflow, 1);
  EXPECT_EQ(arena.count, 3);
  EXPECT_EQ(root, -1);
  EXPECT_EQ(uint32_t(nodes[3].kind), 77u);
  // No arena at all: the material is invalid (-1), nothing is written.
  ctx.arena = nullptr;
  root = 0;
  module->entry(f.fn)(args.data(), &root, &ctx);
  EXPECT_EQ(root, -1);
}

// Every kind of the material algebra, with scalars from the Hit (so they are not constants
// folded at compile time) and a Spectrum weight from the entry's parameter.
const char* kAlgebraSource =
    "import std.spectra.{cauchy}\n"
    "export fn m(h: Hit, w: Spectrum) -> Material =\n"
    "  add_material(\n"
    "    layer(glossy_dielectric(cauchy(1.5, 4200.0), 40.0),\n"
    "          mix_material(conductor(rgb(0.2, 0.4, 0.6), 3.0, roughness: h.uv.y), dielectric(1.5, h.uv.x), 0.5)),\n"
    "    scale_material(add_material(thin_dielectric(1.33), glossy(rgb(0.9, 0.5, 0.1), n: 12)), w))\n";

TEST_P(ClosureLanes, AlgebraNodesCarryChildrenScalarsAndFlags) {
  const int lanes = GetParam();
  BuiltTree t;
  ASSERT_NO_FATAL_FAILURE(buildTree(t, "algebra.tex", kAlgebraSource, lanes, 16));
  ASSERT_EQ(t.arena.count, 10);
  const std::vector<ClosureNode>& nodes = t.nodes;
  const compiler::ClosureArena& arena = t.arena;
  const WavelengthGroup& group = t.group;
  const Value& w = t.w;
  auto node = [&](int32_t i) -> const ClosureNode& {
    EXPECT_TRUE(i >= 0 && i < arena.count) << i;
    return nodes[size_t(std::clamp(i, 0, arena.count - 1))];
  };
  auto isLeaf = [](const ClosureNode& n) { return n.a == -1 && n.b == -1; };

  const ClosureNode& top = node(t.root);
  ASSERT_EQ(top.kind, ClosureKind::Add);
  EXPECT_EQ(top.paramKind, ClosureParam::None);
  EXPECT_EQ(top.flags, 0u);

  const ClosureNode& layer = node(top.a);
  ASSERT_EQ(layer.kind, ClosureKind::Layer);
  EXPECT_EQ(layer.flags, 0u);
  const ClosureNode& coat = node(layer.a);
  ASSERT_EQ(coat.kind, ClosureKind::GlossyDielectric);
  EXPECT_TRUE(isLeaf(coat));
  EXPECT_EQ(coat.paramKind, ClosureParam::Spectrum);
  EXPECT_EQ(coat.flags, compiler::kClosureVariesWithWavelength);
  EXPECT_EQ(coat.scalars[0], 40.0f);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(coat.scalars[i], 0.0f);
  for (int i = 0; i < lanes; ++i)
    EXPECT_EQ(coat.params[i], 1.5f + 4200.0f / (group.lambdaNm[i] * group.lambdaNm[i])) << "lane " << i;

  const ClosureNode& base = node(layer.b);
  ASSERT_EQ(base.kind, ClosureKind::Mix);
  EXPECT_EQ(base.weight, 0.5f);
  const ClosureNode& metal = node(base.a);
  ASSERT_EQ(metal.kind, ClosureKind::Conductor);
  EXPECT_EQ(metal.paramKind, ClosureParam::Color);
  EXPECT_EQ(metal.param2Kind, ClosureParam::Color);
  EXPECT_EQ(metal.params2[1], 3.0f);
  EXPECT_EQ(metal.scalars[0], 0.375f);  // h.uv.y
  EXPECT_EQ(metal.flags, 0u);
  const ClosureNode& rough = node(base.b);
  ASSERT_EQ(rough.kind, ClosureKind::Dielectric);
  EXPECT_EQ(rough.scalars[0], 0.125f);  // h.uv.x
  EXPECT_EQ(rough.flags, 0u);

  const ClosureNode& scale = node(top.b);
  ASSERT_EQ(scale.kind, ClosureKind::Scale);
  EXPECT_EQ(scale.b, -1);
  EXPECT_EQ(scale.paramKind, ClosureParam::Spectrum);
  EXPECT_EQ(scale.flags, compiler::kClosureVariesWithWavelength);  // w is an entry Spectrum
  for (int i = 0; i < lanes; ++i) EXPECT_EQ(scale.params[i], w.f[i]);
  const ClosureNode& sum = node(scale.a);
  ASSERT_EQ(sum.kind, ClosureKind::Add);
  const ClosureNode& thin = node(sum.a);
  ASSERT_EQ(thin.kind, ClosureKind::ThinDielectric);
  EXPECT_TRUE(isLeaf(thin));
  for (int i = 0; i < lanes; ++i) EXPECT_EQ(thin.params[i], 1.33f);
  EXPECT_EQ(thin.scalars[0], 0.0f);
  const ClosureNode& glossy = node(sum.b);
  ASSERT_EQ(glossy.kind, ClosureKind::Glossy);
  EXPECT_EQ(glossy.paramKind, ClosureParam::Color);
  EXPECT_EQ(glossy.params[0], 0.9f);
  EXPECT_EQ(glossy.params[2], 0.1f);
  EXPECT_EQ(glossy.scalars[0], 12.0f);  // an Int n, promoted
  EXPECT_EQ(glossy.flags, 0u);

  // The interpreter builds the same tree, scalars and flags included.
  EXPECT_EQ(t.jitText, t.interpText);
  const Value& interp = t.interp;
  EXPECT_EQ(interp.material->a->b->a->scalars[0], 0.375f);
  EXPECT_EQ(interp.material->b->flags, kMaterialVariesWithWavelength);
  EXPECT_EQ(interp.material->a->a->flags, kMaterialVariesWithWavelength);
  EXPECT_EQ(interp.material->a->b->b->flags, 0u);
}

// An anisotropic roughness (a Vec2 and a rotation, all from the Hit so nothing is folded): the
// node carries kClosureAnisotropic and scalars (alpha_u, alpha_v, rotation) in the JIT and the
// interpreter alike; a Float roughness beside it keeps the isotropic node (flag clear, rotation
// dropped).
TEST_P(ClosureLanes, AnisotropicRoughnessFillsScalarsAndTheFlag) {
  BuiltTree t;
  ASSERT_NO_FATAL_FAILURE(buildTree(t, "aniso.tex",
                                    "export fn m(h: Hit, w: Spectrum) -> Material =\n"
                                    "  add_material(conductor(0.2, 3.0, h.uv.yx, rotation: h.uv.x * 4.0),\n"
                                    "               dielectric(1.5, h.uv.x, 1.0, h.uv.y))\n",
                                    GetParam(), 8));
  ASSERT_EQ(t.arena.count, 3);
  const ClosureNode& metal = t.nodes[0];
  ASSERT_EQ(metal.kind, ClosureKind::Conductor);
  EXPECT_EQ(metal.flags, compiler::kClosureAnisotropic);
  EXPECT_EQ(metal.scalars[0], 0.375f);  // h.uv.y
  EXPECT_EQ(metal.scalars[1], 0.125f);  // h.uv.x
  EXPECT_EQ(metal.scalars[2], 0.5f);    // h.uv.x * 4
  EXPECT_EQ(metal.scalars[3], 0.0f);
  const ClosureNode& glass = t.nodes[1];
  ASSERT_EQ(glass.kind, ClosureKind::Dielectric);
  EXPECT_EQ(glass.flags, 0u);
  EXPECT_EQ(glass.scalars[0], 0.125f);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(glass.scalars[i], 0.0f);
  EXPECT_EQ(t.jitText, t.interpText);
  EXPECT_EQ(t.interp.material->a->flags, kMaterialAnisotropic);
  EXPECT_EQ(t.interp.material->a->scalars[2], metal.scalars[2]);
  EXPECT_EQ(t.interp.material->b->flags, 0u);
}

INSTANTIATE_TEST_SUITE_P(Wavelengths, ClosureLanes, ::testing::Values(4, 8));

TEST(Closure, ConstantSpectrumArgumentsClearTheFlag) {
  // Specialising eta to a constant (a material parameter) makes the conductor wavelength-
  // independent in both the JIT and the interpreter; the Cauchy dielectric still varies.
  Fixture f;
  ASSERT_GE(f.fn, 0);
  Value eta = Value::ofFloat(0.3f);
  int special = f.session.specialise(f.fn, {nullptr, &eta});
  ASSERT_GE(special, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  auto module = compiler::compile(f.session.program(), {special}, options, f.session.diags());
  ASSERT_NE(module, nullptr);
  WavelengthGroup group = groupOf(4);
  std::vector<ClosureNode> nodes(8);
  compiler::ClosureArena arena{nodes.data(), 8, 0, 0};
  compiler::ShadingContext ctx = contextOf(group, &arena);
  std::vector<uint32_t> args;
  Value hit = makeHit(0.5f, 0.5f);
  compiler::flatten(hit, TypeTable::global().hit(), 4, args);
  int32_t root = -1;
  module->entry(special)(args.data(), &root, &ctx);
  ASSERT_GE(root, 0);
  const ClosureNode& metal = nodes[size_t(nodes[size_t(root)].b)];
  ASSERT_EQ(metal.kind, ClosureKind::Conductor);
  EXPECT_EQ(metal.flags, 0u);
  EXPECT_EQ(metal.params[3], 0.3f);
  EXPECT_EQ(nodes[size_t(nodes[size_t(nodes[size_t(root)].a)].a)].flags, compiler::kClosureVariesWithWavelength);
  Value interp = evaluate(f.session.program(), special, {hit}, group);
  ASSERT_TRUE(interp.material);
  EXPECT_EQ(interp.material->b->flags, 0u);
  EXPECT_EQ(interp.material->a->a->flags, kMaterialVariesWithWavelength);
}

// Evaluates a Spectrum-valued std.spectra expression with the interpreter at given wavelengths.
std::vector<float> spectrumAt(const std::string& expr, std::vector<float> lambdas) {
  Session s;
  ModuleInfo* m = s.loadSource("spectra.tex", "import std.spectra.{blackbody, cauchy, sellmeier, bk7}\n"
                                              "fn main() = " + expr + "\n");
  int fn = m ? s.instantiate(m, "main", {}, Span{}) : -1;
  for (auto& d : s.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  if (fn < 0) return {};
  WavelengthGroup g;
  g.count = int(lambdas.size());
  for (size_t i = 0; i < lambdas.size(); ++i) g.lambdaNm[i] = lambdas[i];
  Value v = evaluate(s.program(), fn, {}, g);
  return std::vector<float>(v.f, v.f + lambdas.size());
}

TEST(Spectra, BlackbodyPeaksAtOneAtWiensWavelength) {
  // 5795.5 K peaks at 500 nm (Wien: b / T); the normalised curve is 1 there and below 1 around.
  std::vector<float> b = spectrumAt("blackbody(5795.5439)", {380, 450, 500, 550, 780});
  ASSERT_EQ(b.size(), 5u);
  EXPECT_NEAR(b[2], 1.0f, 1e-5f);
  for (int i : {0, 1, 3, 4}) EXPECT_LT(b[i], b[2]) << i;
  // A cooler body is redder: its 450/650 ratio is smaller.
  std::vector<float> warm = spectrumAt("blackbody(2700.0)", {450, 650});
  std::vector<float> hot = spectrumAt("blackbody(9000.0)", {450, 650});
  EXPECT_LT(warm[0] / warm[1], hot[0] / hot[1]);
  // Planck ratio between two wavelengths at 3000 K, computed in double precision.
  auto planck = [](double nm, double t) { return std::pow(nm, -5.0) / std::expm1(1.438776877e7 / (nm * t)); };
  std::vector<float> cool = spectrumAt("blackbody(3000.0)", {400, 700});
  EXPECT_NEAR(cool[0] / cool[1], planck(400, 3000) / planck(700, 3000), 1e-4);
}

TEST(Spectra, IorsMatchTheirFormulasAndCatalogueValues) {
  std::vector<float> c = spectrumAt("cauchy(1.5, 4200.0)", {400, 700});
  EXPECT_EQ(c[0], 1.5f + 4200.0f / (400.0f * 400.0f));
  EXPECT_EQ(c[1], 1.5f + 4200.0f / (700.0f * 700.0f));
  // N-BK7: nd = 1.5168 at the helium d line (587.6 nm); nF = 1.5224 (486.1), nC = 1.5143 (656.3).
  std::vector<float> n = spectrumAt("bk7()", {587.6f, 486.1f, 656.3f});
  EXPECT_NEAR(n[0], 1.5168f, 1e-4f);
  EXPECT_NEAR(n[1], 1.5224f, 1e-4f);
  EXPECT_NEAR(n[2], 1.5143f, 1e-4f);
  // A one-term Sellmeier with c = 0 is a constant sqrt(1 + b).
  std::vector<float> flat = spectrumAt("sellmeier(1.25, 0.0, 0.0, 0.0, 0.0, 0.0)", {400, 700});
  EXPECT_FLOAT_EQ(flat[0], 1.5f);
  EXPECT_FLOAT_EQ(flat[1], 1.5f);
}

// A zero-argument Spectrum (or Material) expression checked once, evaluated by the interpreter
// at any wavelengths (eight at a time).
class SpectrumProgram {
 public:
  SpectrumProgram(const std::string& imports, const std::string& expr) {
    ModuleInfo* m = session_.loadSource("spectra.tex", imports + "\nfn main() = " + expr + "\n");
    fn_ = m ? session_.instantiate(m, "main", {}, Span{}) : -1;
    for (auto& d : session_.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  }
  bool ok() const { return fn_ >= 0; }
  Value at(const std::vector<float>& lambdas) {
    WavelengthGroup g;
    g.count = int(lambdas.size());
    for (size_t i = 0; i < lambdas.size(); ++i) g.lambdaNm[i] = lambdas[i];
    return evaluate(session_.program(), fn_, {}, g);
  }
  // The Spectrum's value at each wavelength of `lambdas`.
  std::vector<float> sample(const std::vector<float>& lambdas) {
    std::vector<float> out;
    for (size_t i = 0; i < lambdas.size(); i += kMaxLanes) {
      std::vector<float> chunk(lambdas.begin() + long(i), lambdas.begin() + long(std::min(lambdas.size(), i + kMaxLanes)));
      Value v = at(chunk);
      out.insert(out.end(), v.f, v.f + chunk.size());
    }
    return out;
  }

 private:
  Session session_;
  int fn_ = -1;
};

std::vector<float> everyNm(float from, float to) {
  std::vector<float> l;
  for (float x = from; x <= to; x += 1.0f) l.push_back(x);
  return l;
}

TEST(StdSpectra, MetalIorsFollowTheRenderersMeasuredTables) {
  // The generator keeps each reduced table within 0.4% (or 0.001) of the full one.
  const char* imports = "import std.spectra.{gold_eta, gold_k, silver_eta, silver_k, copper_eta, copper_k, aluminium_eta, aluminium_k}";
  const std::pair<const char*, const char*> tables[] = {
      {"gold_eta()", "Au-eta"},   {"gold_k()", "Au-k"},   {"silver_eta()", "Ag-eta"},       {"silver_k()", "Ag-k"},
      {"copper_eta()", "Cu-eta"}, {"copper_k()", "Cu-k"}, {"aluminium_eta()", "Al-eta"}, {"aluminium_k()", "Al-k"}};
  const std::vector<float> lambdas = everyNm(360.0f, 830.0f);
  for (const auto& [expr, name] : tables) {
    SpectrumProgram p(imports, expr);
    ASSERT_TRUE(p.ok()) << expr;
    const auto* table = render::namedSpectrum(name);
    ASSERT_NE(table, nullptr) << name;
    std::vector<float> got = p.sample(lambdas);
    for (size_t i = 0; i < lambdas.size(); ++i) {
      float want = render::interpolateTable(*table, lambdas[i]);
      ASSERT_NEAR(got[i], want, std::max(0.004f * std::abs(want), 0.001f) + 1e-5f) << expr << " at " << lambdas[i] << " nm";
    }
  }
  // The brief's check: gold's eta at 550 nm within 1% of the table.
  SpectrumProgram gold(imports, "gold_eta()");
  float want = render::interpolateTable(*render::namedSpectrum("Au-eta"), 550.0f);
  EXPECT_NEAR(gold.sample({550.0f})[0], want, 0.01f * want);
}

TEST(StdSpectra, CieD65FollowsTheCieTableAndIsOneAt560) {
  SpectrumProgram p("import std.spectra.{cie_d65}", "cie_d65()");
  ASSERT_TRUE(p.ok());
  const std::vector<float> lambdas = everyNm(360.0f, 780.0f);
  std::vector<float> got = p.sample(lambdas);
  for (size_t i = 0; i < lambdas.size(); ++i) {
    float want = color::d65RelativePower(lambdas[i]) / 100.0f;
    ASSERT_NEAR(got[i], want, std::max(0.004f * want, 0.001f) + 1e-5f) << lambdas[i] << " nm";
  }
  EXPECT_NEAR(p.sample({560.0f})[0], 1.0f, 1e-5f);
}

TEST(StdSpectra, IlluminantAIsTheCieFormulaNormalisedAt560) {
  SpectrumProgram p("import std.spectra.{illuminant_a}", "illuminant_a()");
  ASSERT_TRUE(p.ok());
  // CIE 15:2004: S(l) = 100 (560 / l)^5 (e^(c2 / (2848 * 560)) - 1) / (e^(c2 / (2848 l)) - 1), c2 = 1.435e7 nm K.
  auto cie = [](double nm) { return std::pow(560.0 / nm, 5.0) * std::expm1(1.435e7 / (2848.0 * 560.0)) / std::expm1(1.435e7 / (2848.0 * nm)); };
  // The same curve as Planck at 2856 K with today's c2 (within 0.1%).
  auto planck2856 = [](double nm) {
    auto b = [](double l) { return std::pow(l, -5.0) / std::expm1(1.438776877e7 / (l * 2856.0)); };
    return b(nm) / b(560.0);
  };
  const std::vector<float> lambdas = everyNm(360.0f, 830.0f);
  std::vector<float> got = p.sample(lambdas);
  for (size_t i = 0; i < lambdas.size(); ++i) {
    ASSERT_NEAR(got[i], cie(lambdas[i]), 2e-5 * cie(lambdas[i])) << lambdas[i] << " nm";
    ASSERT_NEAR(got[i], planck2856(lambdas[i]), 1e-3 * planck2856(lambdas[i])) << lambdas[i] << " nm";
  }
  EXPECT_NEAR(p.sample({560.0f})[0], 1.0f, 1e-6f);
}

TEST(StdSpectra, Sf11MatchesTheSchottCatalogue) {
  SpectrumProgram p("import std.spectra.{sf11, bk7}", "sf11()");
  ASSERT_TRUE(p.ok());
  // N-SF11 (glass code 785257): nd = 1.78472 at the helium d line (587.6 nm), Abbe number
  // vd = (nd - 1) / (nF - nC) = 25.68 with the hydrogen F (486.1 nm) and C (656.3 nm) lines.
  std::vector<float> n = p.sample({587.5618f, 486.1327f, 656.2725f});
  EXPECT_NEAR(n[0], 1.78472f, 2e-5f);
  EXPECT_NEAR((n[0] - 1.0f) / (n[1] - n[2]), 25.68f, 0.02f);
  // A flint disperses more than a crown: BK7's Abbe number is 64.17.
  SpectrumProgram crown("import std.spectra.{bk7}", "bk7()");
  std::vector<float> c = crown.sample({587.5618f, 486.1327f, 656.2725f});
  EXPECT_NEAR((c[0] - 1.0f) / (c[1] - c[2]), 64.17f, 0.05f);
}

TEST(StdMaterials, LampIsPowerTimesTheBlackbody) {
  SpectrumProgram lamp("import std.materials.{lamp}", "lamp(2700.0, 4.0)");
  SpectrumProgram body("import std.spectra.{blackbody}", "blackbody(2700.0)");
  ASSERT_TRUE(lamp.ok() && body.ok());
  std::vector<float> lambdas = {380, 450, 520, 590, 660, 730, 800, 830};
  Value m = lamp.at(lambdas);
  ASSERT_TRUE(m.material);
  EXPECT_EQ(m.material->kind, MaterialNode::Kind::Emission);
  EXPECT_EQ(m.material->flags, kMaterialVariesWithWavelength);
  std::vector<float> b = body.sample(lambdas);
  for (size_t i = 0; i < lambdas.size(); ++i) EXPECT_EQ(m.material->param.f[i], 4.0f * b[i]) << lambdas[i];
}

TEST(StdMaterials, GoldAt550NmThroughTheJitMatchesTheTable) {
  // The whole path a renderer takes: std.materials' gold compiled at 8 lanes, eta read from the
  // closure node at 550 nm.
  Session session;
  ModuleInfo* m = session.loadSource("gold.tex", "import std.materials.{gold}\nexport fn g() -> Material = gold(0.25)\n");
  int fn = m ? session.instantiate(m, "g", {}, Span{}) : -1;
  for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  options.wavelengths = 8;
  auto module = compiler::compile(session.program(), {fn}, options, session.diags());
  ASSERT_NE(module, nullptr);
  WavelengthGroup group = groupOf(8);
  group.lambdaNm[3] = 550.0f;
  std::vector<ClosureNode> nodes(4);
  compiler::ClosureArena arena{nodes.data(), int32_t(nodes.size()), 0, 0};
  compiler::ShadingContext ctx = contextOf(group, &arena);
  int32_t root = -1;
  module->entry(fn)(nullptr, &root, &ctx);
  ASSERT_EQ(root, 0);
  EXPECT_EQ(nodes[0].kind, ClosureKind::Conductor);
  EXPECT_EQ(nodes[0].scalars[0], 0.25f);
  EXPECT_EQ(nodes[0].flags, compiler::kClosureVariesWithWavelength);
  float eta = render::interpolateTable(*render::namedSpectrum("Au-eta"), 550.0f);
  float k = render::interpolateTable(*render::namedSpectrum("Au-k"), 550.0f);
  EXPECT_NEAR(nodes[0].params[3], eta, 0.01f * eta);
  EXPECT_NEAR(nodes[0].params2[3], k, 0.01f * k);
}

}  // namespace

namespace {

TEST_P(ClosureLanes, SheenCarriesItsRunTimeColourAndRoughness) {
  // A sheen whose Color and roughness are computed from the hit, and std.materials.velvet (a
  // layer of a sheen over a diffuse base): kinds, the Color parameter, the roughness scalar,
  // no wavelength flag, and the interpreter's identical tree.
  const int lanes = GetParam();
  BuiltTree t;
  ASSERT_NO_FATAL_FAILURE(buildTree(
      t, "sheen.tex",
      "import std.materials.{velvet}\n"
      "export fn m(h: Hit, w: Spectrum) -> Material =\n"
      "  add_material(sheen(rgb(h.uv.x, 0.5, 0.25), roughness: h.uv.y), velvet(rgb(0.6, 0.1, 0.2), 0.4))\n",
      lanes, 8));
  ASSERT_EQ(t.arena.count, 5);
  const std::vector<ClosureNode>& nodes = t.nodes;
  const int32_t root = t.root;
  const ClosureNode& top = nodes[size_t(root)];
  ASSERT_EQ(top.kind, ClosureKind::Add);
  const ClosureNode& cloth = nodes[size_t(top.a)];
  ASSERT_EQ(cloth.kind, ClosureKind::Sheen);
  EXPECT_EQ(cloth.a, -1);
  EXPECT_EQ(cloth.paramKind, ClosureParam::Color);
  EXPECT_EQ(cloth.params[0], 0.125f);  // h.uv.x
  EXPECT_EQ(cloth.params[2], 0.25f);
  EXPECT_EQ(cloth.scalars[0], 0.375f);  // h.uv.y
  EXPECT_EQ(cloth.flags, 0u);
  const ClosureNode& velvet = nodes[size_t(top.b)];
  ASSERT_EQ(velvet.kind, ClosureKind::Layer);
  ASSERT_EQ(nodes[size_t(velvet.a)].kind, ClosureKind::Sheen);
  EXPECT_EQ(nodes[size_t(velvet.a)].scalars[0], 0.4f);
  EXPECT_EQ(nodes[size_t(velvet.a)].params[1], std::sqrt(0.1f));  // velvet's sheen is sqrt(color)
  ASSERT_EQ(nodes[size_t(velvet.b)].kind, ClosureKind::Diffuse);
  EXPECT_EQ(nodes[size_t(velvet.b)].params[0], 0.6f);

  EXPECT_EQ(t.jitText, t.interpText);
  EXPECT_EQ(t.interpText,
            "add_material(sheen(rgb(0.125, 0.5, 0.25), 0.375), layer(sheen(rgb(0.7745967, 0.31622776, 0.4472136), "
            "0.4), diffuse(rgb(0.6, 0.1, 0.2))))");
}

}  // namespace
