// Front-end and interpreter benchmarks (issue: the .tex language):
//  - `tex check` work on a generated 10,000-line module (target: under 200 ms);
//  - one REPL line end to end, parse + check + specialise + evaluate (target: under 50 ms),
//    with and without a stdlib import in the session;
//  - interpreter throughput on the marble texture, per pixel;
//  - image() lookups (bilinear and trilinear) from a PNG's stored 8-bit codes against the same
//    image held as floats (what lookups read before round 17).
// Run: build/bin/bench_lang   (the timed CLI runs are in bench/cli_lang.sh)
#include <benchmark/benchmark.h>

#include <string>

#include "lang/image_table.h"
#include "lang/interpreter.h"
#include "lang/session.h"

using namespace tex::lang;

namespace {

// 10,000 lines: a mix of annotated functions, generic helpers and calls between them.
std::string generatedModule() {
  std::string text = "import std.math.{saturate}\n";
  int line = 1;
  for (int i = 0; line < 10000; ++i) {
    text += "fn g" + std::to_string(i) + "(x, s) =\n";
    text += "  let y = x * s + " + std::to_string(i) + ".0 in\n";
    text += "  if y > 1.0 { saturate(y - 1.0) } else { y * y }\n";
    text += "export fn f" + std::to_string(i) + "(h: Hit) -> Float =\n";
    text += "  g" + std::to_string(i) + "(h.uv.x, 2) + g" + std::to_string(i) + "(h.uv.y, 0.5)\n";
    line += 5;
  }
  return text;
}

void BM_Check10kLineModule(benchmark::State& state) {
  std::string text = generatedModule();
  for (auto _ : state) {
    Session session;
    session.loadSource("generated.tex", text);
    if (session.diags().hasErrors()) state.SkipWithError("generated module has errors");
    benchmark::DoNotOptimize(session.program().functions.size());
  }
  state.counters["lines"] = 10000;
}
BENCHMARK(BM_Check10kLineModule)->Unit(benchmark::kMillisecond);

void BM_ReplLine(benchmark::State& state) {
  Session session;
  Expr* expr = nullptr;
  session.addReplInput("import std.noise.{fbm, perlin}", expr, 0);
  int n = 1;
  for (auto _ : state) {
    session.addReplInput("fbm(6, |q| abs(perlin(q)), hit.p * 4.0) + " + std::to_string(n) + ".0", expr, n);
    ++n;
    int fn = session.compileExpression(session.replModule(), expr, {{"hit", TypeTable::global().hit()}});
    if (fn < 0) {
      state.SkipWithError("REPL line failed to compile");
      return;
    }
    Value v = evaluate(session.program(), fn, {makeHit(0.3f, 0.6f)});
    benchmark::DoNotOptimize(v.f[0]);
  }
}
BENCHMARK(BM_ReplLine)->Unit(benchmark::kMillisecond);

void BM_ReplFirstLineWithStdlibImport(benchmark::State& state) {
  for (auto _ : state) {
    Session session;
    Expr* expr = nullptr;
    session.addReplInput("import std.noise.{fbm, perlin}", expr, 0);
    session.addReplInput("fbm(6, |q| abs(perlin(q)), hit.p * 4.0)", expr, 1);
    int fn = session.compileExpression(session.replModule(), expr, {{"hit", TypeTable::global().hit()}});
    Value v = evaluate(session.program(), fn, {makeHit(0.3f, 0.6f)});
    benchmark::DoNotOptimize(v.f[0]);
  }
}
BENCHMARK(BM_ReplFirstLineWithStdlibImport)->Unit(benchmark::kMillisecond);

void BM_InterpretMarblePixel(benchmark::State& state) {
  Session session;
  ModuleInfo* m = session.loadFile(std::string(TEX_SOURCE_DIR) + "/scenes/marble.tex");
  int fn = m ? session.instantiate(m, "marble", {TypeTable::global().hit()}, Span{}) : -1;
  if (fn < 0) {
    state.SkipWithError("scenes/marble.tex does not compile");
    return;
  }
  int i = 0;
  for (auto _ : state) {
    Value v = evaluate(session.program(), fn, {makeHit((i % 512) / 512.0f, (i / 512 % 512) / 512.0f)});
    benchmark::DoNotOptimize(v.f[0]);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InterpretMarblePixel)->Unit(benchmark::kMicrosecond);

}  // namespace

// arg 0: codes (the table's PNG), 1: floats; arg 1: the filter (1 bilinear, 2 trilinear).
void BM_ImageLookup(benchmark::State& state) {
  const ImageLoadResult r = ImageTable::global().load(std::string(TEX_SOURCE_DIR) + "/tests/conformance/images/checker.png", false);
  if (r.handle < 0) return state.SkipWithError(r.message.c_str());
  const LoadedImage& stored = *ImageTable::global().get(r.handle);
  LoadedImage floats;
  ImageLevel base;
  base.width = stored.levels[0].width;
  base.height = stored.levels[0].height;
  base.rgba = stored.levels[0].decoded();
  floats.levels = buildMipPyramid(base);
  const LoadedImage& image = state.range(0) == 0 ? stored : floats;
  const ImageFilter filter = ImageFilter(state.range(1));
  float u = 0.1f, v = 0.7f, sum = 0.0f, out[4];
  for (auto _ : state) {
    u = u + 0.618034f - float(int(u + 0.618034f));
    v = v + 0.414214f - float(int(v + 0.414214f));
    lookupImage(image, filter, 0, u, v, 0.05f, 0.0f, 0.0f, 0.05f, out);
    sum += out[0] + out[3];
  }
  benchmark::DoNotOptimize(sum);
}
BENCHMARK(BM_ImageLookup)->ArgsProduct({{0, 1}, {1, 2}})->ArgNames({"floats", "filter"});

BENCHMARK_MAIN();
