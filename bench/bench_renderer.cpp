// Renderer hot paths on the benchmark scene (scenes/cornell-box-mitsuba.json, the scene of
// cornell_vs_mitsuba.sh), one thread, so that a change to one stage can be measured without
// the noise of whole renders: closest-hit and shadow rays (Embree plus our hit geometry),
// Lambertian BSDF sampling, triangle light sampling, wavelength sampling, a material's shading,
// and whole camera paths. Items are rays, samples or paths; compare items_per_second between
// builds (docs/renderer.md, "Performance").
#include <benchmark/benchmark.h>

#include <optional>
#include <vector>

#include "renderer/bsdf/bsdf.h"
#include "renderer/color/wavelengths.h"
#include "renderer/core/warp.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/sampling/pcg.h"
#include "bench/cornell_bench_scene.h"

namespace {

using namespace tex;
using namespace tex::render;

constexpr int kPool = 4096;  // rays, points and random numbers cycled through by each benchmark

// Random numbers drawn once (drawing them inside a timed loop would cost as much as some of the
// stages measured): dimension d of item i.
constexpr int kDimensions = 16;
float uniform(uint64_t index, int dimension) {
  static const std::vector<float> table = [] {
    std::vector<float> t(size_t(kPool) * kDimensions);
    for (size_t k = 0; k < t.size(); ++k) t[k] = sampling::randomUniform(7, k / kDimensions, int(k % kDimensions));
    return t;
  }();
  return table[size_t(index % kPool) * kDimensions + size_t(dimension)];
}

using Cornell = bench::CornellBenchScene;
const Cornell& cornell() { return bench::cornellBenchScene(); }

void BM_ClosestHit(benchmark::State& state) {
  const Cornell& c = cornell();
  SurfaceHit hit;
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.scene->geometry().intersect(c.rays[i], hit));
    benchmark::DoNotOptimize(hit);
    i = (i + 1) % c.rays.size();
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_ClosestHit);

void BM_ShadowRay(benchmark::State& state) {
  const Cornell& c = cornell();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.scene->geometry().occluded(c.shadowRays[i]));
    i = (i + 1) % c.shadowRays.size();
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_ShadowRay);

void BM_LambertianSample(benchmark::State& state) {
  const Vec3 n = glm::normalize(Vec3(0.2f, 0.9f, 0.1f));
  Bsdf bsdf(Frame::fromNormal(n), n);
  Lobe lobe;
  lobe.kind = LobeKind::Lambertian;
  lobe.weight = Spectrum(0.7f);
  bsdf.add(lobe);
  const Vec3 wo = glm::normalize(Vec3(0.3f, 0.8f, -0.2f));
  uint64_t i = 0;
  for (auto _ : state) {
    const std::optional<BsdfSample> s = bsdf.sample(wo, uniform(i, 0), Vec2(uniform(i, 1), uniform(i, 2)), TransportMode::Radiance);
    benchmark::DoNotOptimize(s);
    i = (i + 1) % kPool;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_LambertianSample);

void BM_TriangleLightSample(benchmark::State& state) {
  const Cornell& c = cornell();
  const Light& light = *c.scene->lights().front();
  const Wavelengths lambda = color::sampleWavelengthGroup(0.3f, 4);
  size_t i = 0;
  for (auto _ : state) {
    const std::optional<LightLiSample> s = light.sampleLiDeferred(c.hitPoints[i], Vec2(uniform(i, 7), uniform(i, 8)), lambda);
    benchmark::DoNotOptimize(s);
    i = (i + 1) % c.hitPoints.size();
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_TriangleLightSample);

void BM_WavelengthGroup(benchmark::State& state) {
  uint64_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(color::sampleWavelengthGroup(uniform(i, 9), 4));
    i = (i + 1) % kPool;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_WavelengthGroup);

// A material's shading at a new wavelength group every time (as at a path's first hit on it;
// later hits replay the per-thread memo).
void BM_MaterialShade(benchmark::State& state) {
  const Cornell& c = cornell();
  SurfaceHit hit;
  c.scene->geometry().intersect(c.rays[0], hit);
  const ShadingPoint sp = RenderScene::shadingPoint(hit);
  const int material = c.scene->materials().materialOfPrimitive(hit.primitive);
  std::vector<Wavelengths> groups;
  for (uint64_t k = 0; k < kPool; ++k) groups.push_back(color::sampleWavelengthGroup(uniform(k, 10), 4));
  uint64_t i = 0;
  for (auto _ : state) {
    const Wavelengths& lambda = groups[i];
    Bsdf bsdf(Frame::fromNormal(sp.ns), sp.ng);
    Spectrum emission;
    benchmark::DoNotOptimize(c.scene->materials().shade(material, sp, lambda, bsdf, emission));
    benchmark::DoNotOptimize(bsdf);
    i = (i + 1) % kPool;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_MaterialShade);

// Whole camera paths as cornell_vs_mitsuba.sh traces them (4 wavelengths, the scene's max depth
// 7 and roulette depth 5), one thread, without the film: the per-path cost every stage above
// adds up to.
void BM_CornellPaths(benchmark::State& state) {
  const Cornell& c = cornell();
  PathTracerSettings settings;
  settings.maxDepth = c.description.settings.maxDepth;
  settings.rouletteDepth = c.description.settings.rouletteDepth;
  settings.filmWidth = settings.filmHeight = 256;
  const PathTracer tracer(*c.scene, sampling::Sampler(sampling::SamplerKind::Sobol, 1), settings);
  uint64_t index = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tracer.record(index));
    ++index;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_CornellPaths);

}  // namespace

BENCHMARK_MAIN();
