// The JIT against the interpreter on real textures, the object cache, the size limit,
// unloading and parallel compiles.
#include <gtest/gtest.h>

#include <chrono>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <fstream>
#include <thread>

#include "compiler/jit.h"
#include "compiler/object_cache.h"
#include "compiler/value_layout.h"
#include "lang/interpreter.h"
#include "lang/session.h"

using namespace tex;
using namespace tex::lang;
namespace fs = std::filesystem;

namespace {

compiler::HitAbi hitAbi(float u, float v) {
  compiler::HitAbi h{};
  h.p[0] = u * 3.7f, h.p[1] = v * 2.3f, h.p[2] = u * v;
  h.n[2] = 1;
  h.uv[0] = u, h.uv[1] = v;
  return h;
}

Value hitValue(const compiler::HitAbi& h) { return makeHit(h.p, h.n, h.uv, 0, 0); }

bool agree(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b || std::fabs(a - b) <= 1e-6f * std::max(1.0f, std::fabs(b));
}

fs::path freshDir(const char* name) {
  fs::path dir = fs::temp_directory_path() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Loaded {
  Session session;
  ModuleInfo* module = nullptr;
  int fn = -1;
};

void load(Loaded& l, const std::string& file, const std::string& name) {
  l.module = l.session.loadFile(std::string(TEX_SOURCE_DIR) + "/" + file);
  ASSERT_NE(l.module, nullptr);
  l.fn = l.session.instantiate(l.module, name, {TypeTable::global().hit()}, Span{});
  for (auto& d : l.session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(l.fn, 0);
}

}  // namespace

class JitAgreesWithInterpreter : public ::testing::TestWithParam<std::tuple<const char*, compiler::OptLevel>> {};

TEST_P(JitAgreesWithInterpreter, OnEveryPixelOfAGrid) {
  auto [name, opt] = GetParam();
  Loaded l;
  load(l, "scenes/marble.tex", name);
  compiler::CompileOptions options;
  options.opt = opt;
  options.useCache = false;
  auto module = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
  ASSERT_NE(module, nullptr);
  const Type* result = l.session.program().functions[size_t(l.fn)].resultType;
  int lanes = result->fixedLanes();
  ASSERT_GT(lanes, 0);
  WavelengthGroup group;
  compiler::ShadingContext ctx{};
  ctx.wavelengthCount = 4;
  for (int i = 0; i < 4; ++i) ctx.lambdaNm[i] = group.lambdaNm[i];
  for (int y = 0; y < 24; ++y) {
    for (int x = 0; x < 24; ++x) {
      compiler::HitAbi h = hitAbi((x + 0.5f) / 24, (y + 0.5f) / 24);
      float jit[8] = {};
      module->entry(l.fn)(&h, jit, &ctx);
      Value interp = evaluate(l.session.program(), l.fn, {hitValue(h)}, group);
      for (int k = 0; k < lanes; ++k)
        ASSERT_TRUE(agree(jit[k], interp.f[k])) << name << " at " << x << "," << y << " lane " << k << ": jit " << jit[k]
                                                << " interp " << interp.f[k];
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Textures, JitAgreesWithInterpreter,
                         ::testing::Combine(::testing::Values("marble", "marble_classic", "wood", "bricks_tex",
                                                              "checker_tex", "cells_tex"),
                                            ::testing::Values(compiler::OptLevel::Quick, compiler::OptLevel::O1)));

TEST(Jit, SpectrumLanesFollowTheContextWavelengths) {
  Session s;
  ModuleInfo* m = s.loadSource("ior.tex", "export fn ior(h: Hit) -> Spectrum = 1.5046 + 4200.0 / (lambda_nm * lambda_nm)\n");
  int fn = s.instantiate(m, "ior", {TypeTable::global().hit()}, Span{});
  ASSERT_GE(fn, 0);
  for (int lanes : {1, 4, 8}) {
    compiler::CompileOptions options;
    options.wavelengths = lanes;
    options.useCache = false;
    auto module = compiler::compile(s.program(), {fn}, options, s.diags());
    ASSERT_NE(module, nullptr);
    compiler::ShadingContext ctx{};
    ctx.wavelengthCount = lanes;
    for (int i = 0; i < lanes; ++i) ctx.lambdaNm[i] = 380.0f + 55.0f * float(i);
    compiler::HitAbi h = hitAbi(0.5f, 0.5f);
    float out[8] = {};
    module->entry(fn)(&h, out, &ctx);
    for (int i = 0; i < lanes; ++i) {
      float lambda = ctx.lambdaNm[i];
      EXPECT_EQ(out[i], 1.5046f + 4200.0f / (lambda * lambda)) << "lane " << i << " of " << lanes;
    }
  }
}

TEST(Jit, MaterialsBuildTheirClosureTreeInTheArena) {
  Session s;
  ModuleInfo* m = s.loadSource("mat.tex",
                               "export fn m(h: Hit) -> Material = mix_material(diffuse(rgb(h.uv.x, 0.5, 0.25)), "
                               "emission(2.0 * lambda_nm), 0.25)\n");
  int fn = s.instantiate(m, "m", {TypeTable::global().hit()}, Span{});
  ASSERT_GE(fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  auto module = compiler::compile(s.program(), {fn}, options, s.diags());
  ASSERT_NE(module, nullptr);
  std::vector<compiler::ClosureNode> nodes(8);
  compiler::ClosureArena arena{nodes.data(), 8, 0, 0};
  compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, &arena};
  compiler::HitAbi h = hitAbi(0.75f, 0.5f);
  int32_t root = -1;
  module->entry(fn)(&h, &root, &ctx);
  ASSERT_EQ(arena.count, 3);
  ASSERT_EQ(root, 2);
  EXPECT_EQ(nodes[2].kind, compiler::ClosureKind::Mix);
  EXPECT_EQ(nodes[2].weight, 0.25f);
  EXPECT_EQ(nodes[nodes[2].a].kind, compiler::ClosureKind::Diffuse);
  EXPECT_EQ(nodes[nodes[2].a].params[0], 0.75f);
  EXPECT_EQ(nodes[nodes[2].b].kind, compiler::ClosureKind::Emission);
  EXPECT_EQ(nodes[nodes[2].b].params[3], 1400.0f);
  // Overflowing the arena is reported, not a crash.
  compiler::ClosureArena tiny{nodes.data(), 1, 0, 0};
  ctx.arena = &tiny;
  module->entry(fn)(&h, &root, &ctx);
  EXPECT_EQ(tiny.overflow, 1);
}

TEST(JitCache, MissThenHitThenCorruptEntriesAreRebuiltNeverLoaded) {
  fs::path dir = freshDir("tex_jit_cache_test");
  Loaded l;
  load(l, "scenes/marble.tex", "marble");
  compiler::CompileOptions options;
  options.cacheDir = dir.string();
  auto evaluate = [&](const compiler::CompiledModule& m) {
    compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, nullptr};
    compiler::HitAbi h = hitAbi(0.3f, 0.6f);
    float out[8] = {};
    m.entry(l.fn)(&h, out, &ctx);
    return std::vector<float>(out, out + 3);
  };
  auto first = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
  ASSERT_NE(first, nullptr);
  EXPECT_FALSE(first->stats().cacheHit);
  std::vector<float> expected = evaluate(*first);
  auto second = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
  ASSERT_NE(second, nullptr);
  EXPECT_TRUE(second->stats().cacheHit);
  EXPECT_EQ(evaluate(*second), expected);

  std::string key = compiler::cacheKey(l.session.program(), {l.fn}, options);
  ASSERT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  fs::path entry = fs::directory_iterator(dir)->path();
  auto size = fs::file_size(entry);
  // Truncated, bit-flipped and foreign entries are all rejected and rebuilt.
  for (int damage = 0; damage < 3; ++damage) {
    std::string bytes;
    {
      std::ifstream in(entry, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    if (damage == 0) bytes.resize(size / 2);
    if (damage == 1) bytes[bytes.size() - 100] ^= 0x40;
    if (damage == 2) bytes.replace(bytes.find("tex-compiler"), 3, "xyz");
    std::ofstream(entry, std::ios::binary | std::ios::trunc) << bytes;
    auto rebuilt = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
    ASSERT_NE(rebuilt, nullptr);
    EXPECT_FALSE(rebuilt->stats().cacheHit) << "damage " << damage;
    EXPECT_TRUE(rebuilt->stats().cacheRejected) << "damage " << damage;
    EXPECT_EQ(evaluate(*rebuilt), expected);
    EXPECT_EQ(fs::file_size(entry), size) << "the entry was rewritten whole";
  }
  // An entry whose framing and checksum are right but whose object does not link (a broken
  // writer, or a build changed without a new compiler version): rebuilt and replaced too. It had
  // been a permanent E0501 until the file was deleted by hand.
  ASSERT_TRUE(compiler::storeCachedObjects(dir.string(), key, {std::string("\x7f" "ELF") + std::string(60, '\0')}));
  auto relinked = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
  for (auto& d : l.session.diags().items()) ADD_FAILURE() << d.message;
  ASSERT_NE(relinked, nullptr);
  EXPECT_TRUE(relinked->stats().cacheRejected);
  EXPECT_EQ(evaluate(*relinked), expected);
  auto afterwards = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
  ASSERT_NE(afterwards, nullptr);
  EXPECT_TRUE(afterwards->stats().cacheHit);
  EXPECT_EQ(evaluate(*afterwards), expected);
  EXPECT_NE(key.find(compiler::hostCpuDescription()), std::string::npos);
}

// Big entries are code-generated on two threads (compiler/parallel_emit.h): two object files
// whose calls into each other resolve at link time, cached together and loaded together.
TEST(JitCache, EntriesEmittedInTwoPartsLinkAndCacheTogether) {
  fs::path dir = freshDir("tex_jit_parts_test");
  Loaded l;
  load(l, "scenes/marble.tex", "cells_tex");
  WavelengthGroup group;
  compiler::ShadingContext ctx{};
  ctx.wavelengthCount = 4;
  for (int i = 0; i < 4; ++i) ctx.lambdaNm[i] = group.lambdaNm[i];
  for (compiler::OptLevel opt : {compiler::OptLevel::Quick, compiler::OptLevel::O1}) {
    compiler::CompileOptions options;
    options.opt = opt;
    options.cacheDir = dir.string();
    for (bool expectHit : {false, true}) {
      auto module = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
      ASSERT_NE(module, nullptr);
      EXPECT_EQ(module->stats().cacheHit, expectHit);
      EXPECT_EQ(module->stats().objectCount, 2u) << "cells_tex should be emitted in two parts";
      for (int i = 0; i < 16; ++i) {
        compiler::HitAbi h = hitAbi((i + 0.5f) / 16, 1.0f - (i + 0.5f) / 16);
        float jit[8] = {};
        module->entry(l.fn)(&h, jit, &ctx);
        Value interp = evaluate(l.session.program(), l.fn, {hitValue(h)}, group);
        for (int k = 0; k < 3; ++k) ASSERT_TRUE(agree(jit[k], interp.f[k])) << "hit " << i << " lane " << k;
      }
    }
  }
}

// Checks `text`, instantiates its exported main(h: Hit) and expects the compiler to refuse it
// with exactly one diagnostic of `code`.
static void expectCompileRefused(const std::string& text, const std::string& code) {
  Session s;
  ModuleInfo* m = s.loadSource("refused.tex", text);
  ASSERT_FALSE(s.diags().hasErrors());
  int fn = s.instantiate(m, "main", {TypeTable::global().hit()}, Span{});
  ASSERT_GE(fn, 0);
  compiler::CompileOptions options;
  options.useCache = false;
  Diagnostics diags;
  EXPECT_EQ(compiler::compile(s.program(), {fn}, options, diags), nullptr);
  ASSERT_EQ(diags.size(), 1u);
  EXPECT_EQ(diags.items()[0].code, code);
}

TEST(Jit, ExponentialSpecialisationIsAnErrorNotAnOutOfMemory) {
  std::string text = "fn g0(x: Float) -> Float = x * 1.5\n";
  for (int i = 1; i < 40; ++i)
    text += "fn g" + std::to_string(i) + "(x: Float) -> Float = g" + std::to_string(i - 1) + "(x) + g" +
            std::to_string(i - 1) + "(x + 1.0)\n";
  text += "export fn main(h: Hit) -> Float = g39(h.uv.x)\n";
  expectCompileRefused(text, "E0413");
}

// Records containing one record twice double with each level: 40 levels are 2^40 words in a
// type of 41 nodes. The compiler refuses the value (E0413) before LLVM lays the type out (it
// hung, lowering the type without memoisation).
TEST(Jit, RecordsSharingStructureAreRefusedBySizeNotLaidOut) {
  std::string nested = "h.uv.x";
  for (int i = 0; i < 40; ++i) nested = "d(" + nested + ")";
  std::string path = "r";
  for (int i = 0; i < 40; ++i) path += ".a";
  const std::string text = "fn d(x) = {a: x, b: x}\nexport fn main(h: Hit) -> Float { let r = " + nested + "; " + path + " }\n";
  const auto start = std::chrono::steady_clock::now();
  expectCompileRefused(text, "E0413");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST(Jit, ManyCompileAndUnloadCyclesStayCorrect) {
  Session s;
  ModuleInfo* m = s.loadSource("cycle.tex", "export fn f(h: Hit) -> Float = h.uv.x * 2.0 + 1.0\n");
  int fn = s.instantiate(m, "f", {TypeTable::global().hit()}, Span{});
  compiler::CompileOptions options;
  options.useCache = false;
  options.opt = compiler::OptLevel::Quick;
  for (int i = 0; i < 300; ++i) {
    auto module = compiler::compile(s.program(), {fn}, options, s.diags());
    ASSERT_NE(module, nullptr);
    compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, nullptr};
    compiler::HitAbi h = hitAbi(0.25f, 0.5f);
    float out = 0;
    module->entry(fn)(&h, &out, &ctx);
    ASSERT_EQ(out, 1.5f);
  }
}

TEST(Jit, ParallelCompilesInTwoThreads) {
  std::vector<std::string> names = {"marble", "wood", "bricks_tex", "checker_tex"};
  std::vector<float> results(names.size() * 2, -1);
  auto work = [&](int thread) {
    for (size_t i = 0; i < names.size(); ++i) {
      Loaded l;
      load(l, "scenes/marble.tex", names[i]);
      compiler::CompileOptions options;
      options.useCache = false;
      auto module = compiler::compile(l.session.program(), {l.fn}, options, l.session.diags());
      if (!module) return;
      compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, nullptr};
      compiler::HitAbi h = hitAbi(0.4f, 0.2f);
      float out[8] = {};
      module->entry(l.fn)(&h, out, &ctx);
      results[size_t(thread) * names.size() + i] = out[0];
    }
  };
  std::thread a(work, 0), b(work, 1);
  a.join();
  b.join();
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_GE(results[i], 0.0f);
    EXPECT_EQ(results[i], results[names.size() + i]) << names[i];
  }
}

TEST(Jit, MaterialParametersAreFoldedBySpecialisation) {
  Session s;
  ModuleInfo* m = s.loadSource("param.tex",
                               "export fn t(h: Hit, scale: Float, octaves: Int) -> Float =\n"
                               "  fold(octaves, 0.0, |a, i| a + sin(h.uv.x * scale * float(i + 1)))\n");
  const Type* hit = TypeTable::global().hit();
  int fn = s.instantiate(m, "t", {hit, TypeTable::global().floating(), TypeTable::global().integer()}, Span{});
  ASSERT_GE(fn, 0);
  Value scale = Value::ofFloat(3.5f), octaves = Value::ofInt(4);
  int special = s.specialise(fn, {nullptr, &scale, &octaves});
  ASSERT_GE(special, 0);
  EXPECT_EQ(s.program().functions[size_t(special)].paramTypes.size(), 1u);
  compiler::CompileOptions options;
  options.useCache = false;
  auto module = compiler::compile(s.program(), {special}, options, s.diags());
  ASSERT_NE(module, nullptr);
  compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, nullptr};
  for (float u : {0.1f, 0.5f, 0.9f}) {
    compiler::HitAbi h = hitAbi(u, 0.5f);
    float jit = 0;
    module->entry(special)(&h, &jit, &ctx);
    Value interp = evaluate(s.program(), fn, {hitValue(h), scale, octaves});
    EXPECT_TRUE(agree(jit, interp.f[0])) << u;
  }
}

// Spectrum sin/cos take a vector path (compiler/codegen.cpp, spectralSinCos): it must stay
// within 1 ulp of the C library the interpreter uses, keep sin(-0) = -0, and fall back for
// huge arguments, NaN and infinities.
TEST(Jit, SpectralSinCosStayWithinOneUlpOfTheCLibrary) {
  Session s;
  ModuleInfo* m = s.loadSource("sincos.tex",
                               "export fn s(h: Hit) -> Spectrum = sin(lambda_nm)\n"
                               "export fn c(h: Hit) -> Spectrum = cos(lambda_nm)\n");
  int fs = s.instantiate(m, "s", {TypeTable::global().hit()}, Span{});
  int fc = s.instantiate(m, "c", {TypeTable::global().hit()}, Span{});
  compiler::CompileOptions options;
  options.useCache = false;
  auto module = compiler::compile(s.program(), {fs, fc}, options, s.diags());
  ASSERT_NE(module, nullptr);
  auto ordered = [](float f) {
    int32_t i;
    std::memcpy(&i, &f, 4);
    return i < 0 ? int64_t(INT32_MIN) - i : int64_t(i);
  };
  compiler::HitAbi h{};
  auto check = [&](const float lanes[4]) {
    compiler::ShadingContext ctx{};
    ctx.wavelengthCount = 4;
    for (int i = 0; i < 4; ++i) ctx.lambdaNm[i] = lanes[i];
    float sinOut[8], cosOut[8];
    module->entry(fs)(&h, sinOut, &ctx);
    module->entry(fc)(&h, cosOut, &ctx);
    for (int i = 0; i < 4; ++i) {
      float x = lanes[i];
      float sx = std::sin(x), cx = std::cos(x);
      if (std::isnan(sx)) {
        EXPECT_TRUE(std::isnan(sinOut[i])) << x;
      } else {
        EXPECT_LE(std::llabs(ordered(sinOut[i]) - ordered(sx)), 1) << "sin " << x;
        EXPECT_EQ(std::signbit(sinOut[i]), std::signbit(sx)) << "sin " << x;
      }
      if (std::isnan(cx)) EXPECT_TRUE(std::isnan(cosOut[i])) << x;
      else EXPECT_LE(std::llabs(ordered(cosOut[i]) - ordered(cx)), 1) << "cos " << x;
    }
  };
  for (double x = -70000.0; x < 70000.0; x += 0.61) {
    const float lanes[4] = {float(x), float(x + 0.013), float(x * 1e-3), float(x * 1e-7)};
    check(lanes);
  }
  const float specials[][4] = {{-0.0f, 0.0f, 1e-40f, -1e-30f},
                               {1e30f, 0.5f, 0.25f, 3.0f},
                               {std::numeric_limits<float>::quiet_NaN(), 1.0f, 2.0f, 3.0f},
                               {std::numeric_limits<float>::infinity(), 1.0f, 2.0f, 3.0f}};
  for (const auto& lanes : specials) check(lanes);
}

// Selects over an integer of a few possible values become constant tables at O1
// (compiler/small_domain_tables.h): a masked field, a shifted field and a remainder, Float
// and Int results, an entry that divides by zero. Every result must be the interpreter's,
// bit for bit, over all 4096 values of the integer the fields come from.
TEST(Jit, SmallDomainSelectsBecomeTablesAndAgreeBitForBit) {
  Session s;
  ModuleInfo* m = s.loadSource("tables.tex",
                               "fn sign_of_bit(g: Int, bit: Int) -> Float = if (g & bit) == 0 { 1.0 } else { -1.0 }\n"
                               "fn coeff(g: Int) -> Float =\n"
                               "  if g < 8 { sign_of_bit(g, 1) } else if g == 12 || g == 14 { 0.5 * sign_of_bit(g, 2) }\n"
                               "  else { 0.0 }\n"
                               "fn field(g: Int) -> Float = if g > 4 { float(g) * 0.25 } else { -1.0 / float(g) }\n"
                               "fn offset(g: Int) -> Int = if g < 6 { g * 7 } else { 100 - g }\n"
                               "export fn t(h: Hit) -> Float {\n"
                               "  let k = int(h.uv.x * 4096.0);\n"
                               "  coeff(k & 15) * h.uv.y + field((k >> 3) & 7) + float(offset((k & 255) % 12))\n"
                               "}\n");
  ASSERT_NE(m, nullptr);
  int fn = s.instantiate(m, "t", {TypeTable::global().hit()}, Span{});
  for (auto& d : s.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(fn, 0);
  for (compiler::OptLevel opt : {compiler::OptLevel::Quick, compiler::OptLevel::O1}) {
    compiler::CompileOptions options;
    options.opt = opt;
    options.useCache = false;
    auto module = compiler::compile(s.program(), {fn}, options, s.diags());
    ASSERT_NE(module, nullptr);
    if (opt == compiler::OptLevel::O1)
      EXPECT_EQ(module->stats().tables, 3u) << "coeff, field and offset should each be one table read";
    else
      EXPECT_EQ(module->stats().tables, 0u) << "quick mode runs no optimisation";
    compiler::ShadingContext ctx{{400, 500, 600, 700}, 4, nullptr};
    for (int k = 0; k < 4096; ++k) {
      compiler::HitAbi h = hitAbi((k + 0.5f) / 4096.0f, 0.3f + 0.0001f * float(k));
      float jit = 0;
      module->entry(fn)(&h, &jit, &ctx);
      Value interp = evaluate(s.program(), fn, {hitValue(h)});
      ASSERT_EQ(std::memcmp(&jit, &interp.f[0], sizeof(float)), 0) << "k " << k << ": jit " << jit << " interp " << interp.f[0];
    }
  }
}
