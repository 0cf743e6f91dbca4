// Image textures in compiled code: bit-for-bit agreement with the interpreter for every filter
// and wrap mode, Image values as entry arguments, runtime-resolved handles with the object
// cache, and cache keys that change when an image file does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include "compiler/jit.h"
#include "compiler/value_layout.h"
#include "lang/image_table.h"
#include "lang/interpreter.h"
#include "lang/session.h"

using namespace tex;
using namespace tex::lang;
namespace fs = std::filesystem;

namespace {

const std::string kImages = std::string(TEX_SOURCE_DIR) + "/tests/conformance/images/";

// One entry: every lookup kind of one image, summed lane-wise into a Vec4 so that any lane
// differing shows.
const char* kSource =
    "export fn f(img: Image, uv: Vec2, dx: Vec2, dy: Vec2, w: Int) -> Vec4 =\n"
    "  vec4(sample(img, uv, w), sample_alpha(img, uv, w)) * 1.0 +\n"
    "  vec4(sample_nearest(img, uv, w), 0.0) * 10.0 +\n"
    "  vec4(sample_filtered(img, uv, dx, dy, w), image_size(img).x) * 100.0\n"
    "export fn g(uv: Vec2, w: Int) -> Color = sample(image(\"checker.png\"), uv, w) + sample(image_data(\"quad.png\"), uv)\n";

struct Program {
  Session session;
  ModuleInfo* module = nullptr;
  explicit Program(const std::string& dir, const std::string& source = kSource) {
    module = session.loadSource(dir + "inline.tex", source);
    for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  }
  int instantiate(const std::string& name, const std::vector<const Type*>& types) {
    int fn = session.instantiate(module, name, types, Span{});
    for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
    return fn;
  }
};

std::vector<const Type*> fTypes() {
  auto& t = TypeTable::global();
  return {t.image(), t.vec(2), t.vec(2), t.vec(2), t.integer()};
}

std::unique_ptr<compiler::CompiledModule> compileOne(Session& session, int fn, bool useCache, const std::string& cacheDir = {}) {
  compiler::CompileOptions options;
  options.useCache = useCache;
  options.cacheDir = cacheDir;
  Diagnostics diags;
  auto module = compiler::compile(session.program(), {fn}, options, diags);
  for (auto& d : diags.items()) ADD_FAILURE() << renderDiagnostic(d);
  return module;
}

Value floats(std::initializer_list<float> xs) {
  Value v;
  int i = 0;
  for (float x : xs) v.f[i++] = x;
  return v;
}

uint32_t bits(float x) {
  uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}

}  // namespace

TEST(ImageJit, AgreesWithTheInterpreterBitForBit) {
  Program p(kImages);
  int fn = p.instantiate("f", fTypes());
  ASSERT_GE(fn, 0);
  auto module = compileOne(p.session, fn, false);
  ASSERT_TRUE(module);
  compiler::EntryFn entry = module->entry(fn);
  int compared = 0;
  for (const char* file : {"checker.png", "quad.png", "hdr.exr", "odd.png"}) {
    ImageLoadResult img = ImageTable::global().load(kImages + file, false);
    ASSERT_GE(img.handle, 0);
    for (int i = 0; i < 1500; ++i) {
      // Coordinates inside, outside and far outside [0, 1], footprints from none to huge.
      float u = float(std::sin(i * 12.9898) * 3.1), v = float(std::cos(i * 78.233) * 2.3);
      float scale = std::ldexp(1.0f, i % 14 - 10);
      Value uv = floats({u, v}), dx = floats({scale * 0.7f, scale * 0.2f}), dy = floats({-scale * 0.1f, scale});
      int32_t wrap = i % 4;  // 3 is not a mode: it wraps as repeat
      std::vector<Value> args = {Value::ofInt(img.handle), uv, dx, dy, Value::ofInt(wrap)};
      Value want = evaluate(p.session.program(), fn, args, WavelengthGroup{});
      std::vector<uint32_t> words;
      const std::vector<const Type*> ts = fTypes();
      for (size_t k = 0; k < args.size(); ++k) compiler::flatten(args[k], ts[k], 4, words);
      std::vector<uint32_t> result(4, 0);
      compiler::ShadingContext ctx{};
      ctx.wavelengthCount = 4;
      entry(words.data(), result.data(), &ctx);
      for (int k = 0; k < 4; ++k)
        ASSERT_EQ(result[size_t(k)], bits(want.f[k])) << file << " uv " << u << "," << v << " lane " << k << " wrap " << wrap;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6000);
}

TEST(ImageJit, ImageConstantsResolveThroughTheCache) {
  // Twice through one cache directory: the second compile is a cache hit and must still find
  // its images (by path: handles differ between processes).
  fs::path cache = fs::temp_directory_path() / ("tex_image_jit_cache_" + std::to_string(::getpid()));
  fs::remove_all(cache);
  auto& types = TypeTable::global();
  std::vector<Value> results;
  for (int round = 0; round < 2; ++round) {
    Program p(kImages);
    int fn = p.instantiate("g", {types.vec(2), types.integer()});
    ASSERT_GE(fn, 0);
    auto module = compileOne(p.session, fn, true, cache.string());
    ASSERT_TRUE(module);
    EXPECT_EQ(module->stats().cacheHit, round == 1);
    for (int i = 0; i < 50; ++i) {
      std::vector<Value> args = {floats({0.013f * float(i), 0.5f - 0.021f * float(i)}), Value::ofInt(i % 3)};
      Value want = evaluate(p.session.program(), fn, args, WavelengthGroup{});
      std::vector<uint32_t> words;
      compiler::flatten(args[0], types.vec(2), 4, words);
      compiler::flatten(args[1], types.integer(), 4, words);
      std::vector<uint32_t> result(3, 0);
      compiler::ShadingContext ctx{};
      ctx.wavelengthCount = 4;
      module->entry(fn)(words.data(), result.data(), &ctx);
      for (int k = 0; k < 3; ++k) ASSERT_EQ(result[size_t(k)], bits(want.f[k])) << "round " << round << " i " << i;
    }
  }
  fs::remove_all(cache);
}

TEST(ImageJit, CacheKeyFollowsTheImageFile) {
  fs::path dir = fs::temp_directory_path() / ("tex_image_jit_key_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(kImages + "quad.png", dir / "t.png", fs::copy_options::overwrite_existing);
  const std::string source = "export fn h(uv: Vec2) -> Color = sample(image(\"t.png\"), uv)\n";
  auto key = [&]() {
    Program p(dir.string() + "/", source);
    int fn = p.instantiate("h", {TypeTable::global().vec(2)});
    EXPECT_GE(fn, 0);
    return compiler::cacheKey(p.session.program(), {fn}, compiler::CompileOptions{});
  };
  std::string first = key();
  EXPECT_EQ(key(), first) << "the same file gives the same key";
  EXPECT_NE(first.find((dir / "t.png").string()), std::string::npos) << "the key names the file";
  fs::copy_file(kImages + "odd.png", dir / "t.png", fs::copy_options::overwrite_existing);
  EXPECT_NE(key(), first) << "an edited image changes the key";
  fs::remove_all(dir);
}

TEST(ImageJit, ImageResultsAndArgumentsAreOneWord) {
  EXPECT_EQ(compiler::wordCount(TypeTable::global().image(), 4), 1u);
  Program p(kImages, "export fn pick(a: Image, b: Image, first: Bool) -> Image = if first { a } else { b }\n");
  auto& types = TypeTable::global();
  int fn = p.instantiate("pick", {types.image(), types.image(), types.boolean()});
  ASSERT_GE(fn, 0);
  auto module = compileOne(p.session, fn, false);
  ASSERT_TRUE(module);
  std::vector<uint32_t> words = {7u, 9u, 0u};
  uint32_t result = 0;
  compiler::ShadingContext ctx{};
  ctx.wavelengthCount = 4;
  module->entry(fn)(words.data(), &result, &ctx);
  EXPECT_EQ(result, 9u);
  Value v = compiler::unflatten(&result, types.image(), 4, nullptr);
  EXPECT_EQ(v.i, 9);
}
