// Front-end and interpreter benchmarks (issue: the .tex language):
//  - `tex check` work on a generated 10,000-line module (target: under 200 ms);
//  - one REPL line end to end, parse + check + specialise + evaluate (target: under 50 ms),
//    with and without a stdlib import in the session;
//  - interpreter throughput on the marble texture, per pixel.
// Run: build/bin/bench_lang   (the timed CLI runs are in bench/cli_lang.sh)
#include <benchmark/benchmark.h>

#include <string>

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

BENCHMARK_MAIN();
