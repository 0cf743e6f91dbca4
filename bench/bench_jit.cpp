// JIT benchmarks (issue: the LLVM ORC JIT). On the textures of bench/textures.tex:
//  1. compile latency, median of single compiles without the cache: O1 <= 10 ms, Quick <= 5 ms;
//     a cache hit (fresh cache directory, entry written by a first compile) <= 1 ms;
//  2. evaluation throughput against the hand-written C++ of bench/native_textures.cpp
//     (-O2 -march=native): geometric mean of the JIT / C++ time ratios <= 1.10, none > 1.25;
//  3. a Spectrum texture compiled for 4 wavelengths costs <= 1.5x the same compiled for 1;
//  4. 10,000 compile-and-unload cycles grow resident memory by <= 5% (after a 200-cycle warm-up).
// Before anything is timed, every texture's JIT result is checked against its C++ twin (and the
// C++ against the reference interpreter) on 4096 hits (256 for the interpreter): they must agree within 1e-4 relative,
// else the program stops, so the comparison is like for like.
//
// Run: build/bin/bench_jit [--benchmark_repetitions=3] [--benchmark_filter=...]
//      TEX_BENCH_RSS_CYCLES=N overrides the 10,000 cycles of the memory test.
// With repetitions, the final table takes the best (lowest) time of the repetitions.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/native_textures.h"
#include "compiler/abi.h"
#include "lang/interpreter.h"
#include "lang/session.h"
#ifdef TEX_BENCH_HAVE_JIT
#include "compiler/jit.h"
#endif

using namespace tex;
using compiler::HitAbi;
using compiler::ShadingContext;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kGrid = 64;
constexpr int kHits = kGrid * kGrid;     // hits per timed pass and for the checks
constexpr int kInterpreterHits = 256;   // the interpreter is slow: check C++ on fewer
constexpr double kTolerance = 1e-4;     // relative (absolute below 1e-3)
constexpr int kLatencySamples = 21;     // single compiles per latency median
constexpr int kRssWarmup = 200;

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

struct Texture {
  std::string name;
  int function = -1;
  const bench::NativeTexture* native = nullptr;
  int outWords = 1;  // with 4 wavelengths
#ifdef TEX_BENCH_HAVE_JIT
  std::unique_ptr<compiler::CompiledModule> jit4;  // O1, 4 wavelengths: the throughput module
  std::unique_ptr<compiler::CompiledModule> jit1;  // spectra: O1, 1 wavelength
#endif
};

struct Fixture {
  lang::Session session;
  lang::ModuleInfo* module = nullptr;
  std::vector<Texture> textures;
  std::vector<HitAbi> hits;
  std::vector<lang::Value> hitValues;
  ShadingContext ctx4{};
  ShadingContext ctx1{};
  std::string cacheDir;
};

Fixture* g = nullptr;

// Figures for the final table; repeated runs keep the best.
struct Figures {
  std::map<std::string, double> jitNs, nativeNs, jit1Ns, native1Ns;  // per evaluation
  std::map<std::string, double> latencyO1, latencyQuick, latencyHit;  // medians, ms
  // O1 compiles without the cache: median of each phase (CompileStats), ms
  std::map<std::string, double> codegenMs, optimiseMs, emitMs, linkMs;
  double rssBefore = 0, rssAfter = 0;
  int rssCycles = 0;
};
Figures figures;

void keepBest(std::map<std::string, double>& m, const std::string& k, double v) {
  auto it = m.find(k);
  if (it == m.end() || v < it->second) m[k] = v;
}

// 64 x 64 hits over the unit square of uv; p is a tilted plane through [-1, 1]^2, so solid
// textures see negative coordinates (floor and int of negatives) and a varying z. Enough hits
// that the branch predictor cannot learn a pass by heart (288 KiB: they stay in L2).
void makeHits(Fixture& f) {
  const float n[3] = {0, 0, 1};
  const float du = 1.0f / 512, dv = 1.0f / 512;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      float u = (i + 0.5f) / kGrid, v = (j + 0.5f) / kGrid;
      float p[3] = {2 * u - 1, 2 * v - 1, 0.25f * (u - v) + 0.1f};
      float uv[2] = {u, v};
      HitAbi h{};
      h.dpdx[0] = du;
      h.dpdy[1] = dv;
      h.duvdx[0] = du;
      h.duvdy[1] = dv;
      for (int k = 0; k < 3; ++k) h.n[k] = n[k], h.p[k] = p[k];
      h.uv[0] = uv[0];
      h.uv[1] = uv[1];
      f.hits.push_back(h);
      f.hitValues.push_back(lang::makeHit(p, n, uv, du, dv));
    }
}

bool close(float got, float want) {
  if (got == want) return true;
  double scale = std::max(std::fabs(double(want)), 1e-3);
  return std::fabs(double(got) - double(want)) <= kTolerance * scale;
}

// Compares `words` outputs; prints the first mismatch. Returns the largest relative error.
bool agree(const char* what, const Texture& t, int hit, const float* got, const float* want, int words,
           double& maxRel) {
  for (int k = 0; k < words; ++k) {
    double rel = std::fabs(double(got[k]) - want[k]) / std::max(std::fabs(double(want[k])), 1e-3);
    maxRel = std::max(maxRel, rel);
    if (!close(got[k], want[k])) {
      const HitAbi& h = g->hits[hit];
      std::fprintf(stderr,
                   "bench_jit: %s disagrees with the C++ twin on texture '%s', hit %d (p = %g %g %g, uv = %g %g), "
                   "word %d: %.9g vs C++ %.9g\n",
                   what, t.name.c_str(), hit, h.p[0], h.p[1], h.p[2], h.uv[0], h.uv[1], k, got[k], want[k]);
      return false;
    }
  }
  return true;
}

#ifdef TEX_BENCH_HAVE_JIT
compiler::CompileOptions options(compiler::OptLevel opt, int wavelengths, bool cache) {
  compiler::CompileOptions o;
  o.opt = opt;
  o.wavelengths = wavelengths;
  o.useCache = cache;
  if (cache) o.cacheDir = g->cacheDir;
  return o;
}

std::unique_ptr<compiler::CompiledModule> compileOrDie(int function, const compiler::CompileOptions& o) {
  auto m = compiler::compile(g->session.program(), {function}, o, g->session.diags());
  if (!m) {
    for (const auto& d : g->session.diags().items()) std::fprintf(stderr, "%s\n", lang::renderDiagnostic(d).c_str());
    std::fprintf(stderr, "bench_jit: compile failed\n");
    std::exit(1);
  }
  return m;
}
#endif

// Loads the textures, compiles them, and checks JIT == C++ == interpreter. Exits on failure.
void setup(Fixture& f) {
  std::string path = std::string(TEX_SOURCE_DIR) + "/bench/textures.tex";
  f.module = f.session.loadFile(path);
  if (!f.module || f.session.diags().hasErrors()) {
    for (const auto& d : f.session.diags().items()) std::fprintf(stderr, "%s\n", lang::renderDiagnostic(d).c_str());
    std::fprintf(stderr, "bench_jit: %s does not load\n", path.c_str());
    std::exit(1);
  }
  makeHits(f);
  const float lambdas[4] = {400, 500, 600, 700};
  for (int k = 0; k < 4; ++k) f.ctx4.lambdaNm[k] = lambdas[k];
  f.ctx4.wavelengthCount = 4;
  f.ctx1.lambdaNm[0] = 550;
  f.ctx1.wavelengthCount = 1;

  int count = 0;
  const bench::NativeTexture* natives = bench::nativeTextures(count);
  for (int i = 0; i < count; ++i) {
    Texture t;
    t.name = natives[i].name;
    t.native = &natives[i];
    t.outWords = natives[i].outWords;
    t.function = f.session.instantiate(f.module, t.name, {lang::TypeTable::global().hit()}, lang::Span{});
    if (t.function < 0) {
      for (const auto& d : f.session.diags().items()) std::fprintf(stderr, "%s\n", lang::renderDiagnostic(d).c_str());
      std::fprintf(stderr, "bench_jit: no texture '%s' in %s\n", t.name.c_str(), path.c_str());
      std::exit(1);
    }
    f.textures.push_back(std::move(t));
  }

  // The C++ twins against the reference interpreter.
  lang::WavelengthGroup group;  // 400, 500, 600, 700 nm
  for (Texture& t : f.textures) {
    double maxRel = 0;
    for (int i = 0; i < kInterpreterHits; ++i) {
      int hit = (i * 37) % kHits;
      lang::Value v = lang::evaluate(f.session.program(), t.function, {f.hitValues[hit]}, group);
      float want[8];
      t.native->fn(f.hits[hit], f.ctx4.lambdaNm, want);
      if (!agree("the reference interpreter", t, hit, v.f, want, t.outWords, maxRel)) std::exit(1);
    }
  }

#ifdef TEX_BENCH_HAVE_JIT
  // The JIT (O1, 4 and 1 wavelengths) against the C++ twins.
  std::printf("%-16s %14s %14s\n", "JIT vs C++", "max rel. diff", "bit-exact");
  for (Texture& t : f.textures) {
    t.jit4 = compileOrDie(t.function, options(compiler::OptLevel::O1, 4, false));
    compiler::EntryFn e4 = t.jit4->entry(t.function);
    compiler::EntryFn e1 = nullptr;
    if (t.native->spectral) {
      t.jit1 = compileOrDie(t.function, options(compiler::OptLevel::O1, 1, false));
      e1 = t.jit1->entry(t.function);
    }
    double maxRel = 0;
    int exact = 0, total = 0;
    for (int i = 0; i < kHits; ++i) {
      float got[8], want[8];
      e4(&f.hits[i], got, &f.ctx4);
      t.native->fn(f.hits[i], f.ctx4.lambdaNm, want);
      if (!agree("the JIT", t, i, got, want, t.outWords, maxRel)) std::exit(1);
      for (int k = 0; k < t.outWords; ++k, ++total) exact += got[k] == want[k];
      if (e1) {
        e1(&f.hits[i], got, &f.ctx1);
        t.native->fn1(f.hits[i], f.ctx1.lambdaNm, want);
        if (!agree("the JIT (1 wavelength)", t, i, got, want, 1, maxRel)) std::exit(1);
      }
    }
    std::printf("%-16s %14.3g %9d/%d\n", t.name.c_str(), maxRel, exact, total);
  }
  std::printf("\n");
#endif
}

// --- throughput -----------------------------------------------------------------------------

void runNative(benchmark::State& state, const Texture* t, bool oneLane) {
  bench::NativeFn fn = oneLane ? t->native->fn1 : t->native->fn;
  const ShadingContext& ctx = oneLane ? g->ctx1 : g->ctx4;
  float out[8];
  float sink = 0;
  auto start = Clock::now();
  for (auto _ : state) {
    for (const HitAbi& h : g->hits) {
      fn(h, ctx.lambdaNm, out);
      sink += out[0];
    }
  }
  double ns = seconds(Clock::now() - start) * 1e9 / (double(state.iterations()) * kHits);
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * kHits);
  keepBest(oneLane ? figures.native1Ns : figures.nativeNs, t->name, ns);
}

#ifdef TEX_BENCH_HAVE_JIT
void runJit(benchmark::State& state, const Texture* t, bool oneLane) {
  compiler::EntryFn fn = (oneLane ? t->jit1 : t->jit4)->entry(t->function);
  const ShadingContext& ctx = oneLane ? g->ctx1 : g->ctx4;
  float out[8];
  float sink = 0;
  auto start = Clock::now();
  for (auto _ : state) {
    for (const HitAbi& h : g->hits) {
      fn(&h, out, &ctx);
      sink += out[0];
    }
  }
  double ns = seconds(Clock::now() - start) * 1e9 / (double(state.iterations()) * kHits);
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * kHits);
  keepBest(oneLane ? figures.jit1Ns : figures.jitNs, t->name, ns);
}

// --- compile latency ------------------------------------------------------------------------

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

void runLatency(benchmark::State& state, const Texture* t, compiler::OptLevel opt, bool cacheHit) {
  compiler::CompileOptions o = options(opt, 4, cacheHit);
  if (cacheHit) compileOrDie(t->function, o);  // writes the entry (or finds it from a previous run)
  std::vector<double> ms, codegen, optimise, emit, link;
  for (auto _ : state) {
    auto start = Clock::now();
    auto m = compileOrDie(t->function, o);
    benchmark::DoNotOptimize(m->entry(t->function));
    double s = seconds(Clock::now() - start);
    if (cacheHit && !m->stats().cacheHit) {
      state.SkipWithError("expected a cache hit");
      return;
    }
    state.SetIterationTime(s);
    ms.push_back(s * 1e3);
    const compiler::CompileStats& st = m->stats();
    codegen.push_back(st.codegenMs);
    optimise.push_back(st.optimiseMs);
    emit.push_back(st.emitMs);
    link.push_back(st.linkMs);
  }
  double med = median(ms);
  if (!cacheHit && opt == compiler::OptLevel::O1) {
    keepBest(figures.codegenMs, t->name, median(codegen));
    keepBest(figures.optimiseMs, t->name, median(optimise));
    keepBest(figures.emitMs, t->name, median(emit));
    keepBest(figures.linkMs, t->name, median(link));
  }
  state.counters["median_ms"] = med;
  auto& table = cacheHit ? figures.latencyHit : opt == compiler::OptLevel::O1 ? figures.latencyO1 : figures.latencyQuick;
  keepBest(table, t->name, med);
}

// --- memory ---------------------------------------------------------------------------------

double residentBytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE));
}

void runCompileUnloadRss(benchmark::State& state, const Texture* t) {
  int cycles = 10000;
  if (const char* env = std::getenv("TEX_BENCH_RSS_CYCLES")) cycles = std::max(1, std::atoi(env));
  compiler::CompileOptions o = options(compiler::OptLevel::O1, 4, false);
  float out[8];
  auto cycle = [&] {
    auto m = compileOrDie(t->function, o);
    m->entry(t->function)(&g->hits[0], out, &g->ctx4);
  };  // the module is destroyed (unloaded) here
  for (auto _ : state) {
    for (int i = 0; i < kRssWarmup; ++i) cycle();
    double before = residentBytes();
    for (int i = 0; i < cycles; ++i) cycle();
    double after = residentBytes();
    figures.rssBefore = before;
    figures.rssAfter = after;
    figures.rssCycles = cycles;
    state.counters["rss_before_MiB"] = before / (1 << 20);
    state.counters["rss_after_MiB"] = after / (1 << 20);
    state.counters["growth_pct"] = 100.0 * (after - before) / before;
  }
}
#endif

void registerBenchmarks(Fixture& f) {
  for (const Texture& t : f.textures) {
#ifdef TEX_BENCH_HAVE_JIT
    benchmark::RegisterBenchmark(("BM_Eval/jit/" + t.name).c_str(), runJit, &t, false)->Unit(benchmark::kMicrosecond);
#endif
    benchmark::RegisterBenchmark(("BM_Eval/native/" + t.name).c_str(), runNative, &t, false)
        ->Unit(benchmark::kMicrosecond);
  }
  for (const Texture& t : f.textures) {
    if (!t.native->spectral) continue;
#ifdef TEX_BENCH_HAVE_JIT
    benchmark::RegisterBenchmark(("BM_EvalOneWavelength/jit/" + t.name).c_str(), runJit, &t, true)
        ->Unit(benchmark::kMicrosecond);
#endif
    benchmark::RegisterBenchmark(("BM_EvalOneWavelength/native/" + t.name).c_str(), runNative, &t, true)
        ->Unit(benchmark::kMicrosecond);
  }
#ifdef TEX_BENCH_HAVE_JIT
  for (const Texture& t : f.textures) {
    benchmark::RegisterBenchmark(("BM_Compile/O1/" + t.name).c_str(), runLatency, &t, compiler::OptLevel::O1, false)
        ->Iterations(kLatencySamples)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Compile/quick/" + t.name).c_str(), runLatency, &t, compiler::OptLevel::Quick,
                                 false)
        ->Iterations(kLatencySamples)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Compile/cache_hit/" + t.name).c_str(), runLatency, &t, compiler::OptLevel::O1,
                                 true)
        ->Iterations(kLatencySamples)->UseManualTime()->Unit(benchmark::kMillisecond);
  }
  const Texture* rssTexture = &f.textures[0];
  for (const Texture& t : f.textures)
    if (t.name == "perlin_tex") rssTexture = &t;
  benchmark::RegisterBenchmark(("BM_CompileUnloadRss/" + rssTexture->name).c_str(), runCompileUnloadRss, rssTexture)
      ->Iterations(1)->Repetitions(1)->Unit(benchmark::kSecond);
#endif
}

// --- the table ------------------------------------------------------------------------------

const char* verdict(bool ok) { return ok ? "ok" : "MISSED"; }
// For figures a filtered run did not measure.
const char* verdict(double value, double limit) { return !(value > 0) ? "not measured" : verdict(value <= limit); }

double lookup(const std::map<std::string, double>& m, const std::string& k) {
  auto it = m.find(k);
  return it == m.end() ? NAN : it->second;
}

void printTable(const Fixture& f) {
  std::printf("\n=== JIT benchmark summary (best of the run's repetitions) ===\n");
  std::printf("host: %ld CPUs\n", sysconf(_SC_NPROCESSORS_ONLN));
  std::printf("\n%-16s %12s %12s %8s   %9s %9s %9s\n", "texture", "JIT ns/eval", "C++ ns/eval", "ratio", "O1 ms",
              "quick ms", "hit ms");
  double logSum = 0, worst = NAN;
  int ratios = 0;
  std::string worstName;
  double worstO1 = NAN, worstQuick = NAN, worstHit = NAN;
  auto worse = [](double& acc, double v) {
    if (std::isfinite(v) && !(acc >= v)) acc = v;
  };
  for (const Texture& t : f.textures) {
    double jit = lookup(figures.jitNs, t.name), nat = lookup(figures.nativeNs, t.name);
    double ratio = jit / nat;
    if (std::isfinite(ratio)) {
      logSum += std::log(ratio);
      ++ratios;
      if (!(worst >= ratio)) worst = ratio, worstName = t.name;
    }
    double o1 = lookup(figures.latencyO1, t.name), quick = lookup(figures.latencyQuick, t.name),
           hit = lookup(figures.latencyHit, t.name);
    if (!std::isfinite(jit) && !std::isfinite(nat) && !std::isfinite(o1) && !std::isfinite(quick) && !std::isfinite(hit))
      continue;  // not in this (filtered) run
    worse(worstO1, o1);
    worse(worstQuick, quick);
    worse(worstHit, hit);
    std::printf("%-16s %12.1f %12.1f %8.3f   %9.2f %9.2f %9.3f\n", t.name.c_str(), jit, nat, ratio, o1, quick, hit);
  }
  double geo = ratios ? std::exp(logSum / ratios) : NAN;
  std::printf("\nthroughput: geometric mean JIT/C++ = %.3f (target <= 1.10: %s); worst %.3f (%s) (target <= 1.25: %s)\n",
              geo, verdict(geo, 1.10), worst, worstName.c_str(), verdict(worst, 1.25));
  std::printf("compile latency medians, worst texture: O1 %.2f ms (<= 10: %s), quick %.2f ms (<= 5: %s), "
              "cache hit %.3f ms (<= 1: %s)\n",
              worstO1, verdict(worstO1, 10), worstQuick, verdict(worstQuick, 5), worstHit, verdict(worstHit, 1));

  if (!figures.codegenMs.empty()) {  // only the textures a filtered run compiled
    std::printf("\nO1 compile phases (medians, ms): codegen = core IR to LLVM IR, optimise = IR passes, emit = "
                "instruction selection to an object, link = JIT loading\n");
    std::printf("%-16s %9s %9s %9s %9s\n", "texture", "codegen", "optimise", "emit", "link");
    for (const Texture& t : f.textures)
      if (figures.codegenMs.count(t.name))
        std::printf("%-16s %9.2f %9.2f %9.2f %9.2f\n", t.name.c_str(), lookup(figures.codegenMs, t.name),
                  lookup(figures.optimiseMs, t.name), lookup(figures.emitMs, t.name), lookup(figures.linkMs, t.name));
  }

  std::printf("\n%-16s %12s %12s %8s   %12s %12s %8s\n", "spectrum", "JIT 4 lanes", "JIT 1 lane", "4 / 1",
              "C++ 4 lanes", "C++ 1 lane", "4 / 1");
  double worstSpectral = NAN;
  for (const Texture& t : f.textures) {
    if (!t.native->spectral) continue;
    double j4 = lookup(figures.jitNs, t.name), j1 = lookup(figures.jit1Ns, t.name);
    double n4 = lookup(figures.nativeNs, t.name), n1 = lookup(figures.native1Ns, t.name);
    if (!std::isfinite(j1) && !std::isfinite(n1)) continue;
    worse(worstSpectral, j4 / j1);
    std::printf("%-16s %12.1f %12.1f %8.3f   %12.1f %12.1f %8.3f\n", t.name.c_str(), j4, j1, j4 / j1, n4, n1, n4 / n1);
  }
  std::printf("spectrum: worst JIT 4-vs-1 wavelength cost ratio %.3f (target <= 1.5: %s)\n", worstSpectral,
              verdict(worstSpectral, 1.5));
  if (figures.rssCycles > 0) {
    double growth = 100.0 * (figures.rssAfter - figures.rssBefore) / figures.rssBefore;
    std::printf("memory: RSS %.1f MiB after %d warm-up cycles, %.1f MiB after %d more compile-and-unload cycles: "
                "%+.2f%% (target <= 5%%: %s)\n",
                figures.rssBefore / (1 << 20), kRssWarmup, figures.rssAfter / (1 << 20), figures.rssCycles, growth,
                verdict(growth <= 5.0));
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // Destroyed before main returns: compiled modules must be unloaded while the compiler's
  // process-wide JIT (a function-local static, created after this) still exists.
  auto owner = std::make_unique<Fixture>();
  Fixture& fixture = *owner;
  g = &fixture;
#ifdef TEX_BENCH_HAVE_JIT
  char dir[] = "/tmp/tex_bench_jit_cache.XXXXXX";
  if (!mkdtemp(dir)) {
    std::perror("bench_jit: mkdtemp");
    return 1;
  }
  fixture.cacheDir = dir;
#else
  std::printf("bench_jit: built without tex_compiler: only the C++ twins are checked and timed\n\n");
#endif
  setup(fixture);
  registerBenchmarks(fixture);
  benchmark::RunSpecifiedBenchmarks();
  printTable(fixture);
  std::fflush(stdout);
  benchmark::Shutdown();
  if (!fixture.cacheDir.empty()) std::filesystem::remove_all(fixture.cacheDir);
  owner.reset();
  g = nullptr;
  return 0;
}
