// `tex eval FILE --fn NAME --size WxH -o OUT`: evaluates a texture over the unit square of uv
// and writes an image. Uses the reference interpreter (the JIT arrives with the compiler).
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "cli/command.h"
#include "cli/option_values.h"
#include "cli/options.h"
#include "cli/texture_evaluator.h"
#include "runtime/cancellation.h"
#include "runtime/progress.h"
#include "lang/interpreter.h"
#include "lang/session.h"
#include "renderer/color/spectral_to_rgb.h"
#include "renderer/image/image_io.h"

namespace tex::cli {
namespace {

const char* kHelp =
    "usage: tex eval FILE --fn NAME [--size WxH] -o OUT.(exr|png) [options]\n\n"
    "Evaluates the texture function NAME(h: Hit) of FILE at the centre of every pixel of the\n"
    "unit square of uv (u to the right, v downwards, as in glTF) and writes an image: OpenEXR\n"
    "(linear, float) or PNG (sRGB-encoded). Hit: p = (u, v, 0), n = (0, 0, 1), uv = (u, v),\n"
    "derivatives one pixel wide. Results: Float (grey), Color, Vec2/3/4 (as RGB) or Spectrum\n"
    "(a reflectance seen under D65, integrated over 32 wavelengths). The texture is compiled by\n"
    "the LLVM JIT (O1) and evaluated on all cores.\n\n"
    "  --fn NAME      the exported or top-level function to evaluate (required)\n"
    "  --size WxH     image size (default 256x256)\n"
    "  -o OUT         output file, .exr or .png (required)\n"
    "  --threads N    worker threads (default: all cores)\n"
    "  --interp       use the reference interpreter instead of the JIT\n"
    "  --no-cache     do not read or write the compiled-code cache\n"
    "  -I DIR         add DIR to the module search path\n"
    "Large images show progress; Ctrl-C stops and writes the partial image (exit 130).\n";

struct Options {
  std::string file, function, output;
  int width = 256, height = 256, threads = 0;
  bool interpret = false;
  compiler::CompileOptions compile;
  lang::SessionOptions session;
};

int parse(const Args& args, Options& o) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](std::string& out) { return takeValue(args, i, out); };
    std::string v;
    if (a == "--fn") {
      if (!value(o.function)) return usageError("eval", "--fn needs a function name");
    } else if (a == "-o" || a == "--output") {
      if (!value(o.output)) return usageError("eval", "-o needs a file name");
    } else if (a == "--size") {
      if (!value(v) || !parseSize(v, o.width, o.height))
        return usageError("eval", "--size needs WxH with 1 <= W, H <= 32768, e.g. 512x512");
    } else if (a == "--threads") {
      if (!value(v) || !parseInt(v, o.threads) || o.threads < 1 || o.threads > 1024)
        return usageError("eval", "--threads needs a count from 1 to 1024");
    } else if (a == "-I") {
      if (!value(v)) return usageError("eval", "-I needs a directory");
      o.session.searchPath.push_back(v);
    } else if (a == "--interp") {
      o.interpret = true;
    } else if (a == "--no-cache") {
      o.compile.useCache = false;
    } else if (!a.empty() && a[0] == '-') {
      return usageError("eval", "unknown option '" + a + "'");
    } else if (o.file.empty()) {
      o.file = a;
    } else {
      return usageError("eval", "more than one input file ('" + o.file + "', '" + a + "')");
    }
  }
  if (o.file.empty()) return usageError("eval", "no input file");
  if (o.function.empty()) return usageError("eval", "--fn NAME is required");
  if (o.output.empty()) return usageError("eval", "-o OUT.exr or -o OUT.png is required");
  std::string ext = std::filesystem::path(o.output).extension().string();
  if (ext != ".exr" && ext != ".png") return usageError("eval", "output must end in .exr or .png, got '" + o.output + "'");
  if (const std::string problem = outputDirectoryProblem(o.output); !problem.empty()) {
    std::fprintf(stderr, "tex eval: error: %s\n", problem.c_str());
    return 1;
  }
  return 0;
}

void printDiagnostics(lang::Session& session) {
  for (const lang::Diagnostic& d : session.diags().items()) std::fputs(lang::renderDiagnostic(d).c_str(), stderr);
}

// Evaluates one pixel to linear RGB.
color::Rgb pixelRgb(const TextureEvaluator& evaluator, const compiler::HitAbi& hit) {
  const lang::Type* t = evaluator.resultType();
  float v[compiler::kMaxWavelengths];
  if (t->kind != lang::TypeKind::Spectrum) {
    const float lambdas[4] = {400, 500, 600, 700};
    evaluator.evaluate(hit, lambdas, 4, v);
  }
  switch (t->kind) {
    case lang::TypeKind::Float: return {v[0], v[0], v[0]};
    case lang::TypeKind::Vec2: return {v[0], v[1], 0};
    case lang::TypeKind::Vec3:
    case lang::TypeKind::Vec4:
    case lang::TypeKind::Color: return {v[0], v[1], v[2]};
    case lang::TypeKind::Spectrum: {
      // 8 stratified hero groups of 4 wavelengths: a noise-free enough look at a reflectance.
      // The 32-point rule alone shows a flat reflectance of 1 as (1.0002, 1.0003, 0.9981): each
      // channel is divided by what the rule gives for that flat 1, so greys are exact.
      constexpr int groups = 8;
      const auto integrate = [&](const auto& valuesAt) {
        color::Rgb sum;
        for (int g = 0; g < groups; ++g) {
          color::WavelengthGroup group = color::sampleWavelengthGroup((g + 0.5f) / (groups * 4.0f), 4);
          valuesAt(group, v);
          color::Rgb rgb = color::reflectanceGroupToLinearSrgb(group, v);
          sum.r += rgb.r / groups;
          sum.g += rgb.g / groups;
          sum.b += rgb.b / groups;
        }
        return sum;
      };
      static const color::Rgb white = integrate([](const color::WavelengthGroup& group, float* out) {
        for (int i = 0; i < group.count; ++i) out[i] = 1.0f;
      });
      const color::Rgb sum = integrate([&](const color::WavelengthGroup& group, float* out) {
        evaluator.evaluate(hit, group.lambdaNm.data(), group.count, out);
      });
      return {sum.r / white.r, sum.g / white.g, sum.b / white.b};
    }
    default: return {0, 0, 0};
  }
}

compiler::HitAbi hitAt(float u, float v, float du, float dv) {
  compiler::HitAbi h{};
  h.p[0] = u, h.p[1] = v, h.p[2] = 0;
  h.n[2] = 1;
  h.uv[0] = u, h.uv[1] = v;
  h.dpdx[0] = du, h.dpdy[1] = dv;
  h.duvdx[0] = du, h.duvdy[1] = dv;
  return h;
}

int runEval(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  Options o;
  if (int rc = parse(args, o)) return rc;
  // Ctrl-C is caught from here on (checking and compiling included), as in tex render.
  std::atomic<bool> cancel{false};
  runtime::ScopedSigintCancellation sigint(cancel);

  lang::Session session(o.session);
  lang::ModuleInfo* module = session.loadFile(o.file);
  if (!module || session.diags().hasErrors()) {
    printDiagnostics(session);
    return 1;
  }
  const lang::FunctionDecl* decl = session.findFunction(module, o.function);
  if (!decl) {
    std::fprintf(stderr, "tex eval: error: %s has no function named '%s'\n", o.file.c_str(), o.function.c_str());
    return 1;
  }
  const lang::Type* hitType = lang::TypeTable::global().hit();
  if (decl->item->params.size() != 1) {
    std::fprintf(stderr, "tex eval: error: '%s' must take exactly one parameter (h: Hit), it takes %zu\n",
                 o.function.c_str(), decl->item->params.size());
    return 1;
  }
  std::vector<const lang::Type*> paramTypes;
  const lang::Type* declaredResult = nullptr;
  if (session.signature(decl, paramTypes, declaredResult) && paramTypes.size() == 1 && paramTypes[0] &&
      paramTypes[0] != hitType) {
    std::fprintf(stderr, "tex eval: error: '%s' takes a %s; eval needs a function of one Hit (h: Hit)\n",
                 o.function.c_str(), lang::typeName(paramTypes[0]).c_str());
    return 1;
  }
  int fn = session.instantiate(module, o.function, {hitType}, decl->item->nameSpan);
  if (fn < 0 || session.diags().hasErrors()) {
    printDiagnostics(session);
    return 1;
  }
  const lang::ir::Program& program = session.program();
  const lang::Type* result = program.functions[size_t(fn)].resultType;
  bool printable = result->isFloatBased();
  if (!printable) {
    std::fprintf(stderr, "tex eval: error: '%s' returns %s; eval needs Float, Vec2/3/4, Color or Spectrum\n",
                 o.function.c_str(), lang::typeName(result).c_str());
    return 1;
  }

  auto evaluator = TextureEvaluator::create(program, fn, o.interpret, o.compile, session.diags());
  if (!evaluator) {
    printDiagnostics(session);
    return 1;
  }

  RgbImage image;
  image.width = o.width;
  image.height = o.height;
  image.rgb.assign(size_t(o.width) * size_t(o.height) * 3, 0.0f);
  size_t nonFinite = 0;
  std::vector<size_t> nonFiniteRows(size_t(o.height), 0);
  auto start = std::chrono::steady_clock::now();
  std::unique_ptr<oneapi::tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<oneapi::tbb::global_control>(oneapi::tbb::global_control::max_allowed_parallelism, size_t(o.threads));
  const float du = 1.0f / float(o.width), dv = 1.0f / float(o.height);
  // Large images take a while: progress every few seconds (pixels as samples), quiet otherwise.
  runtime::ProgressReporter progress("tex eval", uint64_t(o.width) * uint64_t(o.height));
  progress.start();
  // Ctrl-C stops at the next row; rows not evaluated stay black and the image is still written.
  oneapi::tbb::parallel_for(0, o.height, [&](int y) {
    if (cancel.load(std::memory_order_relaxed)) return;
    for (int x = 0; x < o.width; ++x) {
      color::Rgb rgb = pixelRgb(*evaluator, hitAt((float(x) + 0.5f) * du, (float(y) + 0.5f) * dv, du, dv));
      float* out = &image.rgb[(size_t(y) * size_t(o.width) + size_t(x)) * 3];
      float c[3] = {rgb.r, rgb.g, rgb.b};
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(c[k])) {
          ++nonFiniteRows[size_t(y)];
          c[k] = 0;  // NaN/Inf never reach an image; they are counted and reported
        }
        out[k] = c[k];
      }
    }
    progress.add(uint64_t(o.width));
  });
  progress.finish(true);
  for (size_t n : nonFiniteRows) nonFinite += n;
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Whether every row was evaluated, decided before writing (a Ctrl-C during the write must not
  // call a complete image partial), and said in the image too.
  const uint64_t pixelsDone = progress.done();
  const bool interrupted = pixelsDone < uint64_t(o.width) * uint64_t(o.height);
  std::map<std::string, std::string> metadata = {{"tex:source", o.file}, {"tex:function", o.function}};
  if (interrupted)
    metadata["tex:interrupted"] = std::to_string(pixelsDone) + " of " + std::to_string(uint64_t(o.width) * uint64_t(o.height)) +
                                  " pixels evaluated; the others are black";
  std::string err = writeRgbImage(o.output, image, metadata);
  if (!err.empty()) {
    std::fprintf(stderr, "tex eval: error: %s\n", err.c_str());
    return 1;
  }
  std::string how = "interpreter";
  if (evaluator->compiled()) {
    const compiler::CompileStats& stats = evaluator->module()->stats();
    char buf[96];
    std::snprintf(buf, sizeof buf, "JIT O1, compiled in %.1f ms%s", stats.milliseconds, stats.cacheHit ? " (cache hit)" : "");
    how = buf;
  }
  std::fprintf(stderr, "tex eval: %s %dx%d in %.2f s (%.2f Mpixel/s, %s)%s\n", o.output.c_str(), o.width, o.height,
               seconds, double(progress.done()) / seconds * 1e-6, how.c_str(),
               interrupted ? " (interrupted: rows not evaluated are black)" : "");
  if (nonFinite)
    std::fprintf(stderr, "tex eval: warning: %zu non-finite channel values (NaN/Inf) were written as 0\n", nonFinite);
  return interrupted ? 130 : 0;  // 128 + SIGINT, as tex render
}

}  // namespace

TEX_COMMAND("eval", "evaluate a texture function over the unit square into an image", &runEval);

}  // namespace tex::cli
