// Table 1 of the thesis (docs/thesis.md, "Results to reproduce"): image error of the spectral
// techniques on single-scattering glossy dispersive refraction, for C = 1, 4, 16, 64, 256
// samples per pixel. A1 = the proposed technique (wavelength group + spectral MIS, the path
// tracer's `mis` mode), A2 = one wavelength per path (`single`). Scenes: scenes/table1/
// (n = 1000, IOR 1.35..1.20; n = 4000, IOR 1.50..1.20).
//
// Per setting: a long `mis` reference (seed 0) and a long `single` render (seed 1) that must
// agree with it within noise (both estimators are unbiased; a Z-test on 8 x 8 pixel blocks),
// then `--seeds` renders per (C, mode) with seeds 100, 101, ... and the RMSE against the
// reference, averaged over the seeds. The error is normalised: every image is scaled by
// 0.5 / (mean of the reference over pixels and R, G, B), so that the reference's mean is 0.5
// (the RMSE of an unnormalised render depends on the scene's exposure; the thesis's numbers
// are of the same order on its own scale). The reference's own noise, which every RMSE
// includes, is printed as the "floor" (sqrt of its mean pixel variance, normalised alike).
//
// usage: bench_table1 [--res N] [--ref-spp N] [--check-spp N] [--seeds K] [--wavelengths 4|8] [--threads T] [--out DIR] [--only n1000|n4000]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/film/film_sink.h"
#include "renderer/image/image_io.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/scene/load_scene.h"
#include "runtime/stream.h"

namespace {

using namespace tex;
using namespace tex::render;

struct Options {
  int res = 32;
  int refSpp = 4096;
  int checkSpp = 0;  // the single-mode agreement render; 0: refSpp
  int seeds = 8;
  int wavelengths = 4;  // per path: 4 or 8
  int threads = 0;
  std::string outDir;
  std::string only;
};

struct Setting {
  const char* name;
  const char* scene;
  const char* label;
  double thesisA1[5], thesisA2[5];
};

constexpr int kSpp[5] = {1, 4, 16, 64, 256};

const Setting kSettings[2] = {
    {"n1000", "glossy_n1000.json", "n = 1000, IOR 1.35 -> 1.20",
     {0.126, 0.0667, 0.0263, 0.0122, 0.00532},
     {0.247, 0.202, 0.134, 0.0756, 0.0383}},
    {"n4000", "glossy_n4000.json", "n = 4000, IOR 1.50 -> 1.20",
     {0.207, 0.133, 0.0739, 0.0384, 0.0174},
     {0.246, 0.196, 0.129, 0.0737, 0.0372}},
};

DevelopedImage render(const RenderScene& rs, const Options& o, SpectralMode mode, int spp, uint64_t seed, int maxDepth,
                      PathCounters* counters = nullptr) {
  PathTracerSettings settings;
  settings.maxDepth = maxDepth;
  settings.spectralMode = mode;
  settings.wavelengths = o.wavelengths;
  const PathTracer tracer(rs, sampling::Sampler(sampling::SamplerKind::Sobol, seed), settings);
  FilmSettings fs;
  fs.width = fs.height = o.res;
  FilmSink sink(fs);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&sink};
  runtime::SchedulerOptions options;
  options.threads = o.threads;
  options.chunkSize = 4096;
  runtime::runStream<SampleRecord>({0, uint64_t(o.res) * uint64_t(o.res) * uint64_t(spp)}, options, tracer,
                                   std::span<runtime::Sink<SampleRecord>* const>(sinks));
  if (counters) *counters = tracer.counters();
  return sink.film().develop();
}

double meanOf(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += x;
  return v.empty() ? 0.0 : s / double(v.size());
}

double rmse(const DevelopedImage& a, const DevelopedImage& ref) {
  double s = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) s += (double(a.rgb[i]) - ref.rgb[i]) * (double(a.rgb[i]) - ref.rgb[i]);
  return std::sqrt(s / double(a.rgb.size()));
}

// Worst |z| over 8 x 8 pixel blocks and channels of (a - b) / sqrt(var a + var b): block sums
// are close to normal even where single pixels are heavy-tailed.
double worstBlockZ(const DevelopedImage& a, const DevelopedImage& b, int& blocks) {
  const int bs = 8, nb = a.width / bs;
  double worst = 0;
  blocks = 0;
  for (int by = 0; by < nb; ++by)
    for (int bx = 0; bx < nb; ++bx)
      for (int c = 0; c < 3; ++c) {
        double d = 0, v = 0;
        for (int y = by * bs; y < by * bs + bs; ++y)
          for (int x = bx * bs; x < bx * bs + bs; ++x) {
            const size_t i = (size_t(y) * size_t(a.width) + size_t(x)) * 3 + size_t(c);
            d += double(a.rgb[i]) - b.rgb[i];
            v += double(a.variance[i]) + b.variance[i];
          }
        if (v <= 0) continue;
        ++blocks;
        worst = std::max(worst, std::fabs(d) / std::sqrt(v));
      }
  return worst;
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void writeImage(const Options& o, const std::string& name, const DevelopedImage& img) {
  if (o.outDir.empty()) return;
  std::filesystem::create_directories(o.outDir);
  const std::string path = o.outDir + "/" + name + ".exr";
  if (std::string e = writeExr(path, img.toExr(true, false, {})); !e.empty()) std::fprintf(stderr, "%s\n", e.c_str());
}

int runSetting(const Setting& s, const Options& o) {
  std::string error;
  const std::string path = std::string(TEX_SOURCE_DIR) + "/scenes/table1/" + s.scene;
  std::optional<SceneDescription> scene = loadScene(path, error);
  if (!scene) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  RenderSceneOptions ro;
  ro.width = ro.height = o.res;
  ro.wavelengths = o.wavelengths;
  std::unique_ptr<RenderScene> rs = RenderScene::build(*scene, ro, error);
  if (!rs) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const int maxDepth = scene->settings.maxDepth;
  std::printf("## %s (%s, %dx%d, max depth %d, %d wavelengths per path)\n", s.label, s.scene, o.res, o.res, maxDepth,
              o.wavelengths);

  auto t0 = std::chrono::steady_clock::now();
  PathCounters counters;
  const DevelopedImage ref = render(*rs, o, SpectralMode::Mis, o.refSpp, 0, maxDepth, &counters);
  const double refSeconds = seconds(t0);
  writeImage(o, std::string(s.name) + "_reference_mis", ref);
  const double mean = meanOf(ref.rgb);
  if (!(mean > 0)) {
    std::printf("reference is black (mean %g): nothing to compare\n", mean);
    return 1;
  }
  const double scale = 0.5 / mean;
  const double floor = std::sqrt(meanOf(ref.variance)) * scale;
  std::printf("reference: mis, %d spp, %.1f s (%.2f Mpaths/s), mean %.6g (scale %.6g), %llu non-finite, noise floor %.3g\n",
              o.refSpp, refSeconds, double(o.res) * o.res * o.refSpp / refSeconds * 1e-6, mean, scale,
              (unsigned long long)counters.nonFiniteSamples, floor);

  // Both techniques are unbiased: a long `single` render must match the reference in noise.
  t0 = std::chrono::steady_clock::now();
  const int checkSpp = o.checkSpp > 0 ? o.checkSpp : o.refSpp;
  const DevelopedImage singleRef = render(*rs, o, SpectralMode::Single, checkSpp, 1, maxDepth);
  writeImage(o, std::string(s.name) + "_reference_single", singleRef);
  int blocks = 0;
  const double z = worstBlockZ(singleRef, ref, blocks);
  // Bonferroni-corrected two-sided 1% over the blocks: z of about 4.4 for 768 tests.
  const bool agree = z < 4.4;
  std::printf("agreement: single %d spp (%.1f s) vs the mis reference: mean %.6g vs %.6g, normalised RMSE %.3g, worst block |z| %.2f over %d blocks: %s\n",
              checkSpp, seconds(t0), meanOf(singleRef.rgb), mean, rmse(singleRef, ref) * scale, z, blocks,
              agree ? "agree" : "DISAGREE");

  // "corrected": the reference's own noise (independent of the run's) taken out in quadrature.
  std::printf("\n| C | A1 mis | A2 single | A2/A1 | A2/A1 corrected | thesis A1 | thesis A2 | thesis A2/A1 |\n"
              "|---|---|---|---|---|---|---|---|\n");
  bool misWins = true;
  for (int c = 0; c < 5; ++c) {
    double err[2] = {0, 0};
    const SpectralMode modes[2] = {SpectralMode::Mis, SpectralMode::Single};
    for (int m = 0; m < 2; ++m) {
      for (int k = 0; k < o.seeds; ++k) {
        const DevelopedImage img = render(*rs, o, modes[m], kSpp[c], 100 + uint64_t(k), maxDepth);
        err[m] += rmse(img, ref) * scale;
        if (k == 0 && (kSpp[c] == 1 || kSpp[c] == 16))
          writeImage(o, std::string(s.name) + "_" + spectralModeName(modes[m]) + "_spp" + std::to_string(kSpp[c]), img);
      }
      err[m] /= o.seeds;
    }
    misWins = misWins && err[0] < err[1];
    const auto corrected = [&](double e) { return std::sqrt(std::max(0.0, e * e - floor * floor)); };
    std::printf("| %d | %.4g | %.4g | %.2f | %.2f | %.3g | %.3g | %.2f |\n", kSpp[c], err[0], err[1], err[1] / err[0],
                corrected(err[1]) / corrected(err[0]), s.thesisA1[c], s.thesisA2[c], s.thesisA2[c] / s.thesisA1[c]);
    std::fflush(stdout);
  }
  std::printf("\nmis beats single at every C: %s\n\n", misWins ? "yes" : "NO");
  return agree && misWins ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    if (a == "--res" && hasValue) o.res = std::atoi(argv[++i]);
    else if (a == "--ref-spp" && hasValue) o.refSpp = std::atoi(argv[++i]);
    else if (a == "--check-spp" && hasValue) o.checkSpp = std::atoi(argv[++i]);
    else if (a == "--seeds" && hasValue) o.seeds = std::atoi(argv[++i]);
    else if (a == "--wavelengths" && hasValue) o.wavelengths = std::atoi(argv[++i]);
    else if (a == "--threads" && hasValue) o.threads = std::atoi(argv[++i]);
    else if (a == "--out" && hasValue) o.outDir = argv[++i];
    else if (a == "--only" && hasValue) o.only = argv[++i];
    else {
      std::fprintf(stderr,
                   "usage: bench_table1 [--res N (multiple of 8)] [--ref-spp N] [--check-spp N] [--seeds K] [--wavelengths 4|8] [--threads T] [--out DIR] "
                   "[--only n1000|n4000]\n");
      return 2;
    }
  }
  if (o.res < 8 || o.res % 8 != 0 || o.refSpp < 1 || o.seeds < 1 || (o.wavelengths != 4 && o.wavelengths != 8)) {
    std::fprintf(stderr, "bench_table1: bad options\n");
    return 2;
  }
  int status = 0;
  for (const Setting& s : kSettings)
    if (o.only.empty() || o.only == s.name) status = std::max(status, runSetting(s, o));
  return status;
}
